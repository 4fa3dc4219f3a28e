// Computes a field with the installed library: the paper's array under the line2d and
// layered conductors, the second derivative of the potential below the centre of electrode
// 4 for 1 mA, against a centred finite difference of the potential itself.
#include <cmath>
#include <cstdio>
#include <vector>

#include "model/conductor.hpp"

int main() {
  const tp::ElectrodeArray array = tp::ElectrodeArray::paper();
  for (const char* name : {"line2d", "layered"}) {
    tp::ConductorParams params;
    params.model = name;
    const auto c = tp::make_conductor(params, array);
    const std::size_t n = c->size(), e = 3;
    const double x = array.positions_mm[e], y = 0.9, h = 1e-3;
    std::vector<double> xx(n), yy(n), p0(n), pu(n), pd(n);
    c->unit_second_derivatives(x, y, xx.data(), yy.data());
    c->unit_potentials(x, y, p0.data());
    c->unit_potentials(x, y + h, pu.data());
    c->unit_potentials(x, y - h, pd.data());
    const double fd = (pu[e] - 2 * p0[e] + pd[e]) / (h * h);
    std::printf("%s %.9g %.9g\n", name, yy[e], fd);
    if (!(std::fabs(yy[e] - fd) <= 1e-4 * std::fabs(fd))) return 1;
  }
  return 0;
}
