#include "estimation/ekf/joint_compatibility.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <limits>
#include <set>

#include "estimation/chi_square.h"

namespace splam::estimation {
namespace {

class Search {
 public:
  Search(const std::vector<CompatibilityItem>& items, const std::function<bool(int, int)>& conflict,
         const Eigen::MatrixXd& p, double probability, long max_nodes)
      : items_(items),
        conflict_(conflict),
        p_(p),
        probability_(probability),
        max_nodes_(max_nodes) {}

  JointCompatibilityResult Run() {
    std::vector<int> chosen;
    Recurse(0, &chosen, 0.0);
    best_.nodes = nodes_;
    best_.exhaustive = nodes_ < max_nodes_;
    return best_;
  }

 private:
  // D^2 of the set, or infinity when S is not positive definite. H is taken on the state columns
  // the set involves (the robot's and its landmarks'), d of them: S = H P_d H^T + R directly when
  // the set has at most d rows, else by the matrix inversion lemma,
  //   D^2 = nu^T R^-1 nu - b^T (P_d^-1 + H^T R^-1 H)^-1 b,  b = H^T R^-1 nu,
  // which costs O(rows d^2) instead of O(rows^3) (the B-spline EKF's hundreds of beams).
  double JointD2(const std::vector<int>& set) const {
    std::vector<Eigen::Index> columns{0, 1, 2};
    Eigen::Index rows = 0;
    for (const int i : set) {
      const CompatibilityItem& item = items_[static_cast<std::size_t>(i)];
      rows += item.innovation.size();
      for (const JacobianBlock& b : item.blocks)
        for (Eigen::Index c = 0; c < b.jacobian.cols(); ++c) columns.push_back(b.start + c);
    }
    std::sort(columns.begin(), columns.end());
    columns.erase(std::unique(columns.begin(), columns.end()), columns.end());
    const auto d = static_cast<Eigen::Index>(columns.size());
    const auto compact = [&](Eigen::Index column) {
      return static_cast<Eigen::Index>(std::lower_bound(columns.begin(), columns.end(), column) -
                                       columns.begin());
    };
    Eigen::MatrixXd h = Eigen::MatrixXd::Zero(rows, d);
    Eigen::MatrixXd r = Eigen::MatrixXd::Zero(rows, rows);
    Eigen::VectorXd nu(rows);
    Eigen::Index row = 0;
    for (const int i : set) {
      const CompatibilityItem& item = items_[static_cast<std::size_t>(i)];
      const Eigen::Index k = item.innovation.size();
      nu.segment(row, k) = item.innovation;
      h.block(row, 0, k, 3) = item.h_robot;
      for (const JacobianBlock& b : item.blocks)
        for (Eigen::Index c = 0; c < b.jacobian.cols(); ++c)
          h.block(row + b.first_row, compact(b.start + c), b.jacobian.rows(), 1) +=
              b.jacobian.col(c);
      r.block(row, row, k, k) = item.noise;
      row += k;
    }
    Eigen::MatrixXd p(d, d);
    for (Eigen::Index a = 0; a < d; ++a)
      for (Eigen::Index b = 0; b < d; ++b) p(a, b) = p_(columns[a], columns[b]);
    constexpr double kInfinity = std::numeric_limits<double>::infinity();
    if (rows > d) {
      const Eigen::LLT<Eigen::MatrixXd> r_llt(r);
      const Eigen::LLT<Eigen::MatrixXd> p_llt(p);
      if (r_llt.info() == Eigen::Success && p_llt.info() == Eigen::Success) {
        const Eigen::MatrixXd r_inv_h = r_llt.solve(h);
        const Eigen::VectorXd r_inv_nu = r_llt.solve(nu);
        const Eigen::MatrixXd a =
            p_llt.solve(Eigen::MatrixXd::Identity(d, d)) + h.transpose() * r_inv_h;
        const Eigen::VectorXd b = h.transpose() * r_inv_nu;
        const Eigen::LLT<Eigen::MatrixXd> a_llt(a);
        if (a_llt.info() != Eigen::Success) return kInfinity;
        return nu.dot(r_inv_nu) - b.dot(a_llt.solve(b));
      }
    }
    const Eigen::LLT<Eigen::MatrixXd> s_llt(h * p * h.transpose() + r);
    if (s_llt.info() != Eigen::Success) return kInfinity;
    return nu.dot(s_llt.solve(nu));
  }

  bool Compatible(const std::vector<int>& chosen, int item) const {
    const CompatibilityItem& it = items_[static_cast<std::size_t>(item)];
    return std::none_of(chosen.begin(), chosen.end(), [&](int c) {
      return items_[static_cast<std::size_t>(c)].group == it.group ||
             (conflict_ && conflict_(c, item));
    });
  }

  // The groups from item `from` on that could still join `chosen`: an upper bound on how many
  // more items the branch can take.
  int Reachable(std::size_t from, const std::vector<int>& chosen) const {
    std::set<int> groups;
    for (std::size_t i = from; i < items_.size(); ++i)
      if (Compatible(chosen, static_cast<int>(i))) groups.insert(items_[i].group);
    return static_cast<int>(groups.size());
  }

  void Recurse(std::size_t next, std::vector<int>* chosen, double d2) {
    const int size = static_cast<int>(chosen->size());
    const int best_size = static_cast<int>(best_.chosen.size());
    if (size > best_size || (size == best_size && size > 0 && d2 < best_.d2)) {
      best_.chosen = *chosen;
      best_.d2 = d2;
    }
    if (next >= items_.size() || nodes_ >= max_nodes_) return;
    if (size + Reachable(next, *chosen) <= static_cast<int>(best_.chosen.size())) return;
    const int item = static_cast<int>(next);
    if (Compatible(*chosen, item)) {
      chosen->push_back(item);
      ++nodes_;
      Eigen::Index rows = 0;
      for (const int i : *chosen) rows += items_[static_cast<std::size_t>(i)].innovation.size();
      const double joint = JointD2(*chosen);
      if (joint <= ChiSquareQuantile(probability_, static_cast<double>(rows)))
        Recurse(next + 1, chosen, joint);
      chosen->pop_back();
    }
    Recurse(next + 1, chosen, d2);
  }

  const std::vector<CompatibilityItem>& items_;
  const std::function<bool(int, int)>& conflict_;
  const Eigen::MatrixXd& p_;
  double probability_;
  long max_nodes_;
  JointCompatibilityResult best_;
  long nodes_ = 0;
};

}  // namespace

JointCompatibilityResult JointCompatibility(const std::vector<CompatibilityItem>& items,
                                            const std::function<bool(int, int)>& conflict,
                                            const Eigen::MatrixXd& covariance, double probability,
                                            long max_nodes) {
  return Search(items, conflict, covariance, probability, max_nodes).Run();
}

}  // namespace splam::estimation
