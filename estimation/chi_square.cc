#include "estimation/chi_square.h"

#include <boost/math/distributions/chi_squared.hpp>

namespace splam::estimation {

double ChiSquareQuantile(double p, double dof) {
  return boost::math::quantile(boost::math::chi_squared_distribution<double>(dof), p);
}

}  // namespace splam::estimation
