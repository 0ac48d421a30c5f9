#include "kernel/curvature.h"

#include <cmath>

namespace splam::kernel {

Status CurvatureOptions::Validate() const {
  // The kernels span 3 sigma either side in samples: a sigma of kilometres would ask for 10^9.
  if (!(sigma_m > 0.0 && sigma_m <= 10.0))
    return Status::Error("curvature sigma_m must be in (0, 10] m");
  if (!(padding_fwhm >= 0.0 && padding_fwhm <= 10.0))
    return Status::Error("curvature padding_fwhm must be in [0, 10]");
  return Status::Ok();
}

CurvatureProfile ComputeCurvature(const std::vector<Eigen::Vector2d>& samples, double epsilon_m,
                                  const CurvatureOptions& options) {
  CurvatureProfile profile;
  profile.epsilon_m = epsilon_m;
  const int n = static_cast<int>(samples.size());
  profile.curvature.assign(samples.size(), 0.0);
  if (n < 3 || !(epsilon_m > 0.0)) {
    profile.smoothed = samples;
    return profile;
  }
  // Kernels over [-w, w] samples, w = 3 sigma.
  const double s = std::max(options.sigma_m / epsilon_m, 0.5);
  const int w = std::max(1, static_cast<int>(std::ceil(3.0 * s)));
  std::vector<double> g(2 * w + 1), g1(2 * w + 1), g2(2 * w + 1);
  double sum = 0.0, m1 = 0.0, m2 = 0.0, sum2 = 0.0;
  for (int k = -w; k <= w; ++k) {
    const double e = std::exp(-0.5 * k * k / (s * s));
    g[k + w] = e;
    g1[k + w] = -k / (s * s) * e;
    g2[k + w] = (k * k / (s * s) - 1.0) / (s * s) * e;
    sum += e;
    sum2 += g2[k + w];
  }
  for (int k = -w; k <= w; ++k) {
    g[k + w] /= sum;
    g2[k + w] -= sum2 / (2 * w + 1);  // the second derivative of a constant is 0
    m1 += k * g1[k + w];
    m2 += k * k * g2[k + w];
  }
  // (x * g1)(i) = sum_k x(i - k) g1(k): a ramp x = i gives -sum k g1(k), which must be 1; a
  // parabola x = i^2 / 2 gives sum k^2 g2(k) / 2, which must be 1.
  for (int k = -w; k <= w; ++k) {
    g1[k + w] /= -m1;
    g2[k + w] *= 2.0 / m2;
  }
  // Padding by point reflection at both ends.
  const double fwhm = 2.0 * std::sqrt(2.0 * std::log(2.0)) * s;
  const int pad = std::max(w, static_cast<int>(std::ceil(options.padding_fwhm * fwhm)));
  auto at = [&](int i) -> Eigen::Vector2d {
    if (i < 0) return 2.0 * samples[0] - samples[std::min(-i, n - 1)];
    if (i >= n) return 2.0 * samples[n - 1] - samples[std::max(2 * (n - 1) - i, 0)];
    return samples[i];
  };
  std::vector<Eigen::Vector2d> padded(n + 2 * pad);
  for (int i = -pad; i < n + pad; ++i) padded[i + pad] = at(i);

  profile.smoothed.resize(samples.size());
  for (int i = 0; i < n; ++i) {
    Eigen::Vector2d p = Eigen::Vector2d::Zero(), d1 = Eigen::Vector2d::Zero(),
                    d2 = Eigen::Vector2d::Zero();
    for (int k = -w; k <= w; ++k) {
      const Eigen::Vector2d& x = padded[i - k + pad];
      p += g[k + w] * x;
      d1 += g1[k + w] * x;
      d2 += g2[k + w] * x;
    }
    profile.smoothed[i] = p;
    const double speed2 = d1.squaredNorm();
    profile.curvature[i] =
        speed2 > 0.0 ? (d1.x() * d2.y() - d2.x() * d1.y()) / (speed2 * std::sqrt(speed2)) : 0.0;
  }
  return profile;
}

void CurvatureOptions::VisitFields(FieldVisitor& v) {
  v.Field("sigma_m", &sigma_m, "scale of the Gaussian smoothing, arc length in m");
  v.Field("padding_fwhm", &padding_fwhm, "each end padded by this many FWHM of samples");
}

}  // namespace splam::kernel
