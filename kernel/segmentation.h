#ifndef SPLAM_KERNEL_SEGMENTATION_H_
#define SPLAM_KERNEL_SEGMENTATION_H_

#include <Eigen/Core>
#include <string>
#include <vector>

#include "kernel/options.h"
#include "kernel/scan.h"
#include "kernel/status.h"

namespace splam::kernel {

// A run of consecutive hits of one scan that belong to one object, in the sensor frame.
struct ScanSegment {
  std::vector<Eigen::Vector2d> points;
  std::vector<std::size_t> beams;  // beam index of each point, increasing

  // Length of the polyline through the points, metres.
  double Length() const;
};

enum class SegmentationMethod {
  kDietmayer,  // adaptive distance threshold (paper 000 §3.1): keeps corners inside segments
  kPedraza,    // spacing ratio and alignment tests (paper 000 §2a): splits at sharp corners
};

struct SegmentationOptions {
  SegmentationMethod method = SegmentationMethod::kDietmayer;

  // Dietmayer: consecutive hits a, b join when |a - b| <= c0 + C1 min(r_a, r_b), with
  // C1 = sqrt(2 (1 - cos dalpha)) the spacing of two beams at equal range. c0 absorbs the
  // range noise: about 3 sigma of the sensor at mid range.
  double dietmayer_c0_m = 0.10;

  // Pedraza: with p_i = d_i - d_(i-1), point i+1 joins while
  // max(|p_i|, |p_i+1|) <= eta min(|p_i|, |p_i+1|) (spacing) and the angle between p_i and
  // p_i+1 is at most alpha_max (alignment). The first gap of a segment, which has no
  // predecessor, must be at most pedraza_max_gap_m.
  double pedraza_eta = 2.0;                  // in [1.5, 2] in the paper
  double pedraza_alpha_max_rad = 0.7853982;  // pi/4, the paper's upper bound
  double pedraza_max_gap_m = 0.3;

  // Segments shorter than this (polyline length) or with fewer points are dropped: too little
  // information, and it filters people and small moving objects.
  double min_length_m = 0.25;
  int min_points = 5;

  // Describes every field (key, unit, comment) to a visitor: the YAML form.
  void VisitFields(kernel::FieldVisitor& v);
  Status Validate() const;
};

// Splits the hits of a scan into segments, in beam order. A reading that is not a hit
// (no-return, invalid, out of range) always ends the current segment.
std::vector<ScanSegment> SegmentScan(const Scan& scan, const SegmentationOptions& options = {});

}  // namespace splam::kernel

#endif  // SPLAM_KERNEL_SEGMENTATION_H_
