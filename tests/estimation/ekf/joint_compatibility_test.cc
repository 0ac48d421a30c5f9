// Joint compatibility branch and bound: the largest jointly compatible set of pairings.
#include "estimation/ekf/joint_compatibility.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <random>
#include <set>

#include "estimation/chi_square.h"

namespace splam::estimation {
namespace {

// Point landmarks observed as z = l - r (position only): state [rx, ry, rth, l1x, l1y, ...].
CompatibilityItem PointPairing(int group, int landmark, const Eigen::Vector2d& z,
                               const Eigen::VectorXd& state, double sigma_m) {
  CompatibilityItem item;
  item.group = group;
  const Eigen::Index at = 3 + 2 * landmark;
  item.innovation = z - (state.segment<2>(at) - state.head<2>());
  item.h_robot = Eigen::MatrixXd::Zero(2, 3);
  item.h_robot.leftCols(2) = -Eigen::Matrix2d::Identity();
  item.blocks = {JacobianBlock{at, Eigen::Matrix2d::Identity(), 0}};
  item.noise = sigma_m * sigma_m * Eigen::Matrix2d::Identity();
  return item;
}

// Two landmarks 1 m apart, the robot 0.7 m from where it believes (sigma 1 m): observation b
// lies nearest landmark 1, so the nearest neighbour pairs b with 1 and then a with 2, both inside
// the individual gate. Only a-1, b-2 is explained by one robot offset: JCBB takes it.
TEST(JointCompatibility, PairsWhatOneRobotOffsetExplains) {
  Eigen::VectorXd state = Eigen::VectorXd::Zero(7);
  state.segment<2>(5) = Eigen::Vector2d(1.0, 0.0);
  Eigen::MatrixXd p = 1e-4 * Eigen::MatrixXd::Identity(7, 7);
  p(0, 0) = p(1, 1) = 1.0;
  const Eigen::Vector2d robot(0.7, 0.0);
  const Eigen::Vector2d za = state.segment<2>(3) - robot, zb = state.segment<2>(5) - robot;
  std::vector<CompatibilityItem> items{
      PointPairing(0, 0, za, state, 0.01), PointPairing(0, 1, za, state, 0.01),
      PointPairing(1, 0, zb, state, 0.01), PointPairing(1, 1, zb, state, 0.01)};
  const int landmark[] = {0, 1, 0, 1};
  const auto same = [&](int a, int b) { return landmark[a] == landmark[b]; };
  const JointCompatibilityResult r = JointCompatibility(items, same, p, 0.95);
  EXPECT_EQ(r.chosen, (std::vector<int>{0, 3}));
  EXPECT_NEAR(r.d2, 0.49, 0.01);  // the offset, whitened by the robot's sigma
  EXPECT_TRUE(r.exhaustive);
}

// An item of many rows (a B-spline's beams) on few state columns: D^2 by the matrix inversion
// lemma equals nu^T (H P H^T + R)^-1 nu computed whole, and a large enough innovation fails the
// joint gate of that many rows.
TEST(JointCompatibility, ManyRowsOnFewColumnsGiveTheDirectDistance) {
  std::mt19937 gen(9);
  std::normal_distribution<double> n(0.0, 1.0);
  const Eigen::Index state = 9, rows = 40;
  Eigen::MatrixXd l = Eigen::MatrixXd::Random(state, state);
  const Eigen::MatrixXd p =
      0.01 * l * l.transpose() + 1e-3 * Eigen::MatrixXd::Identity(state, state);
  CompatibilityItem item;
  item.h_robot = Eigen::MatrixXd::Random(rows, 3);
  item.blocks = {JacobianBlock{5, Eigen::MatrixXd::Random(rows, 4), 0}};
  Eigen::VectorXd variance(rows);
  for (Eigen::Index k = 0; k < rows; ++k) variance(k) = 1e-3 * static_cast<double>(1 + k % 3);
  item.noise = variance.asDiagonal();
  Eigen::MatrixXd h = Eigen::MatrixXd::Zero(rows, state);
  h.leftCols(3) = item.h_robot;
  h.middleCols(5, 4) = item.blocks[0].jacobian;
  const Eigen::MatrixXd s = h * p * h.transpose() + item.noise;
  item.innovation = s.llt().matrixL() * Eigen::VectorXd::NullaryExpr(rows, [&] { return n(gen); });
  const double direct = item.innovation.dot(s.llt().solve(item.innovation));
  const JointCompatibilityResult r = JointCompatibility({item}, {}, p, 0.999);
  ASSERT_EQ(r.chosen.size(), 1u);
  EXPECT_NEAR(r.d2, direct, 1e-6 * direct);
  item.innovation *= 3.0;  // D^2 nine times chi^2(40)'s mean
  EXPECT_TRUE(JointCompatibility({item}, {}, p, 0.999).chosen.empty());
}

// Random scenes (fixed seed): the set JCBB returns is jointly compatible, one to one, and as
// large as the largest compatible set found by trying every assignment.
TEST(JointCompatibility, PropertyTheSetIsTheLargestJointlyCompatibleOne) {
  std::mt19937 gen(3);
  std::normal_distribution<double> n(0.0, 1.0);
  std::uniform_real_distribution<double> u(0.0, 3.0);
  for (int trial = 0; trial < 40; ++trial) {
    const int landmarks = 4, observations = 3;
    Eigen::VectorXd state = Eigen::VectorXd::Zero(3 + 2 * landmarks);
    for (int l = 0; l < landmarks; ++l) state.segment<2>(3 + 2 * l) << u(gen), 0.3 * u(gen);
    Eigen::MatrixXd p = 1e-3 * Eigen::MatrixXd::Identity(state.size(), state.size());
    p(0, 0) = p(1, 1) = 0.3;
    const Eigen::Vector2d robot(0.5 * n(gen), 0.5 * n(gen));
    std::vector<CompatibilityItem> items;
    std::vector<int> landmark_of;
    for (int o = 0; o < observations; ++o) {
      const Eigen::Vector2d z =
          state.segment<2>(3 + 2 * o) - robot + 0.02 * Eigen::Vector2d(n(gen), n(gen));
      for (int l = 0; l < landmarks; ++l) {
        items.push_back(PointPairing(o, l, z, state, 0.05));
        landmark_of.push_back(l);
      }
    }
    const auto same = [&](int a, int b) { return landmark_of[a] == landmark_of[b]; };
    const JointCompatibilityResult r = JointCompatibility(items, same, p, 0.95);
    // Every assignment of the observations (a landmark each, or none), one to one.
    std::size_t largest = 0;
    std::vector<int> pick(observations, -1);
    const std::function<void(int)> all = [&](int o) {
      if (o == observations) {
        std::vector<int> set;
        std::set<int> used;
        for (int k = 0; k < observations; ++k)
          if (pick[k] >= 0) {
            if (!used.insert(pick[k]).second) return;
            set.push_back(k * landmarks + pick[k]);
          }
        if (set.size() <= largest) return;
        const JointCompatibilityResult single = JointCompatibility(
            [&] {
              std::vector<CompatibilityItem> only;
              for (const int i : set) only.push_back(items[static_cast<std::size_t>(i)]);
              return only;
            }(),
            {}, p, 0.95);
        if (single.chosen.size() == set.size()) largest = set.size();
        return;
      }
      for (int l = -1; l < landmarks; ++l) {
        pick[o] = l;
        all(o + 1);
      }
    };
    all(0);
    EXPECT_EQ(r.chosen.size(), largest) << "trial " << trial;
    std::set<int> groups, used;
    for (const int c : r.chosen) {
      EXPECT_TRUE(groups.insert(items[static_cast<std::size_t>(c)].group).second);
      EXPECT_TRUE(used.insert(landmark_of[static_cast<std::size_t>(c)]).second);
    }
    EXPECT_LE(r.d2, ChiSquareQuantile(0.95, 2.0 * static_cast<double>(r.chosen.size())) + 1e-9);
  }
}

}  // namespace
}  // namespace splam::estimation
