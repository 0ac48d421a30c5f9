#ifndef SPLAM_ESTIMATION_EKF_EKF_METHODS_H_
#define SPLAM_ESTIMATION_EKF_EKF_METHODS_H_

#include "estimation/slam_method.h"
#include "kernel/registry.h"

namespace splam::estimation {

// The EKF-SLAM methods behind the SlamMethod interface, as the registry's built-ins
// "ekf-lines" (EkfLineSlam, paper 001) and "ekf-bspline" (EkfBSplineSlam, paper 000).
void AddEkfMethods(kernel::Registry<SlamMethodInfo>* registry);

}  // namespace splam::estimation

#endif  // SPLAM_ESTIMATION_EKF_EKF_METHODS_H_
