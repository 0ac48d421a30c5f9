#ifndef SPLAM_ESTIMATION_CHI_SQUARE_H_
#define SPLAM_ESTIMATION_CHI_SQUARE_H_

namespace splam::estimation {

// The p-quantile of the chi-square distribution with `dof` degrees of freedom, 0 < p < 1
// (e.g. ChiSquareQuantile(0.95, 2) = 5.99, the gate of paper 001).
double ChiSquareQuantile(double p, double dof);

}  // namespace splam::estimation

#endif  // SPLAM_ESTIMATION_CHI_SQUARE_H_
