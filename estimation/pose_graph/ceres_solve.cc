#include "estimation/pose_graph/ceres_solve.h"

namespace splam::estimation {

ceres::Solver::Summary SolveSilently(ceres::Problem* problem, ceres::LinearSolverType solver_type,
                                     int max_iterations) {
  ceres::Solver::Options solver;
  solver.linear_solver_type = solver_type;
  solver.max_num_iterations = max_iterations;
  solver.logging_type = ceres::SILENT;
  solver.num_threads = 1;
  ceres::Solver::Summary summary;
  ceres::Solve(solver, problem, &summary);
  return summary;
}

}  // namespace splam::estimation
