// The response-curve error measure shared by the HDR tests.
#pragma once

#include <cmath>

#include "hdr/response_curve.h"

namespace hdribr::test {

// RMS of exp(g - g_true - offset) - 1 over lo..245 DN of channel c, offset the mean log
// difference there (a response is known up to a scale): the relative error of the linear
// exposure the curve gives back.
inline double RmsLinearError(const ResponseCurve& got, const ResponseCurve& truth, int c,
                             int lo = 10) {
  const int n = 245 - lo + 1;
  double offset = 0;
  for (int z = lo; z <= 245; ++z) offset += got.log_inverse[c][z] - truth.log_inverse[c][z];
  offset /= n;
  double sum = 0;
  for (int z = lo; z <= 245; ++z) {
    const double e = std::exp(got.log_inverse[c][z] - truth.log_inverse[c][z] - offset) - 1.0;
    sum += e * e;
  }
  return std::sqrt(sum / n);
}

}  // namespace hdribr::test
