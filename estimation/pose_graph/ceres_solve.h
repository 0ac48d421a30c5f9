#ifndef SPLAM_ESTIMATION_POSE_GRAPH_CERES_SOLVE_H_
#define SPLAM_ESTIMATION_POSE_GRAPH_CERES_SOLVE_H_

#include <ceres/problem.h>
#include <ceres/solver.h>

namespace splam::estimation {

// Solves `problem` with Ceres on one thread without logging (the graph SLAM's registration and
// pose graph run beside other work and inside tests).
ceres::Solver::Summary SolveSilently(ceres::Problem* problem, ceres::LinearSolverType solver_type,
                                     int max_iterations);

}  // namespace splam::estimation

#endif  // SPLAM_ESTIMATION_POSE_GRAPH_CERES_SOLVE_H_
