#ifndef SPLAM_KERNEL_CURVATURE_H_
#define SPLAM_KERNEL_CURVATURE_H_

#include <Eigen/Core>
#include <string>
#include <vector>

#include "kernel/options.h"
#include "kernel/status.h"

namespace splam::kernel {

struct CurvatureOptions {
  // Scale of the Gaussian g(u, sigma) that smooths the curve (paper 000 eq. 8-9), as an arc
  // length in metres: small enough to remove only noise.
  double sigma_m = 0.05;
  // Each end is padded with this many FWHM of samples (FWHM = 2 sqrt(2 ln 2) sigma); paper 000
  // pads with twice the FWHM. Padding continues the curve by point reflection, x_-k = 2 x_0 - x_k,
  // which keeps straight ends straight.
  double padding_fwhm = 2.0;

  // Describes every field (key, unit, comment) to a visitor: the YAML form.
  void VisitFields(kernel::FieldVisitor& v);
  Status Validate() const;
};

// A curve sampled every epsilon of arc length, smoothed, with its signed curvature.
struct CurvatureProfile {
  double epsilon_m = 0.0;
  std::vector<Eigen::Vector2d> smoothed;  // X(u, sigma) = X(u) * g(u, sigma)
  // k(u, sigma) = (x_u y_uu - x_uu y_u) / (x_u^2 + y_u^2)^(3/2), 1/m, positive when the curve
  // turns left (counter-clockwise); x_u = x * g_u, x_uu = x * g_uu (paper 000 eq. 11-15).
  std::vector<double> curvature;
};

// Smooths equally spaced samples (spacing epsilon_m) and computes their curvature with
// derivative-of-Gaussian kernels. Fewer than 3 samples give zero curvature and the samples
// unchanged. The kernels are normalised so that a straight line has curvature exactly 0 and a
// parabola its exact second derivative.
CurvatureProfile ComputeCurvature(const std::vector<Eigen::Vector2d>& samples, double epsilon_m,
                                  const CurvatureOptions& options = {});

}  // namespace splam::kernel

#endif  // SPLAM_KERNEL_CURVATURE_H_
