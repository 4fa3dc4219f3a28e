#pragma once
// The output stage behind the pulse engine: a multi-channel DAC whose channels change
// together, and the output-enable line of the electrode switches.  Codes are signed,
// + = cathodic, 0 = no current.

#include <cstddef>
#include <cstdint>

namespace tp::fw {

class OutputStage {
 public:
  // Prepares the next codes of channels 0..n-1 (not yet output).
  virtual void load(const std::int16_t* codes, std::size_t n) = 0;
  // Outputs the prepared codes on every channel at once.
  virtual void latch() = 0;
  // The codes the outputs now hold, per the driver's copy of the DAC's registers (what it
  // wrote and latched).
  virtual void output(std::int16_t* codes, std::size_t n) const = 0;
  // The electrode switches: closed only while output runs.
  virtual void enable(bool on) = 0;
  virtual bool enabled() const = 0;
  // Transfers that did not complete (a peripheral that never became ready): the firmware
  // stops the output for good (an output fault) at the first.
  virtual std::uint32_t faults() const = 0;

 protected:
  ~OutputStage() = default;  // never deleted through this interface (and no heap to do it)
};

}  // namespace tp::fw
