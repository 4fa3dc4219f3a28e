// What the fibre models' unit tests share.
#pragma once

#include <memory>
#include <vector>

#include "fibre/models.hpp"
#include "model/field.hpp"

namespace tp::test {

// The paper's array and SAI pattern (docs/fibres.md), with the MRG fibre.
struct PaperCase {
  Setup setup;
  std::vector<double> w{0, 0, -0.5, 1, -0.5, 0, 0, 0};
  std::unique_ptr<Conductor> conductor = make_conductor(setup.conductor, setup.array);
  std::unique_ptr<fibre::FibreModel> model = fibre::make_fibre_model("mrg");
  const Receptor& sai() const { return setup.receptors[1]; }
};

}  // namespace tp::test
