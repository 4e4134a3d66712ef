#include "core/photo.h"

namespace hdribr {

double Exposure::Relative() const {
  const double t = time_s.value_or(1.0);
  const double iso_gain = iso ? *iso / 100.0 : 1.0;
  const double n = f_number.value_or(1.0);
  return t * iso_gain / (n * n);
}

}  // namespace hdribr
