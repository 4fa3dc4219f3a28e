#pragma once
// Analog Devices AD5628 / AD5648 / AD5668: octal 12/14/16-bit DACs with an SPI input, a
// 32-bit input word, an internal 1.25 V reference (x2: 0 to 2.5 V out) and an LDAC pin
// that moves every input register to its DAC register at once (AD5628/AD5648/AD5668 data
// sheet, Rev. G: "Serial interface", tables 8 and 9 (command and address bits), "LDAC
// function").  Currents are offset binary around mid-scale: a signed code c is written as
// 2^(bits-1) + c, and the front end's current sources turn mid-scale into 0 mA
// (firmware/README.md).  SPI2, mode 2 (SCLK idles high, data taken on its falling edge),
// 16-bit frames, two per 32-bit word, SYNC low around each word.

#include "board.hpp"
#include "output_stage.hpp"

namespace tp::fw {

class DacAd56x8 final : public OutputStage {
 public:
  static constexpr std::size_t kChannels = 8;
  // bits: 12 (AD5628), 14 (AD5648) or 16 (AD5668).  Resets the part, turns its reference
  // on and puts every channel at mid-scale (0 mA).
  void init(const Board& board, int bits);
  void load(const std::int16_t* codes, std::size_t n) override;
  void latch() override;
  void output(std::int16_t* codes, std::size_t n) const override;
  void enable(bool on) override;
  bool enabled() const override { return enabled_; }
  std::uint32_t faults() const override { return faults_; }

 private:
  bool write_word(std::uint32_t word);  // false: the SPI never became ready (counted)
  static constexpr std::uint32_t kUnknown = 0xFFFFFFFFu;  // a register after a fault
  std::uint32_t value_of(std::int16_t code) const;

  const Board* board_ = nullptr;
  int bits_ = 12;
  std::uint32_t input_[kChannels] = {};  // what each input register holds
  std::uint32_t dac_[kChannels] = {};    // what each DAC register (the output) holds
  bool enabled_ = false;
  std::uint32_t faults_ = 0;
};

}  // namespace tp::fw
