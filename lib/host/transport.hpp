#pragma once
// The byte transport under the stimulator client, chosen by the port name (as libsigrok's
// serial backends): "emu" is the in-process emulator (the device core behind an in-memory
// link); a pseudo-terminal (stim-emu's) goes through POSIX termios, because libserialport
// cannot open ptys on Linux; anything else is a serial port opened through libserialport.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "device/protocol.hpp"
#include "device/skin_scenario.hpp"

namespace tp::host {

class Transport {
 public:
  virtual ~Transport() = default;
  virtual std::string name() const = 0;
  // Writes all bytes or throws tp::Error (failure).
  virtual void write(const std::uint8_t* data, std::size_t n) = 0;
  // Waits up to timeout_ms for at least one byte; returns how many were read (0: timeout).
  // Throws tp::Error (failure) when the link is lost.
  virtual std::size_t read(std::uint8_t* buf, std::size_t max, int timeout_ms) = 0;
  // The OS descriptor of a serial line (for the emergency stop), or -1.
  virtual int native_handle() const { return -1; }
};

// The skin an emulator's electrodes touch (--emu-skin, stim-emu --skin; docs/skin.md):
// none, an ideal load (records carry no measurements); else every pulse is measured.
struct EmulatorSkin {
  std::shared_ptr<const device::SkinScenario> scenario;
  double compliance_V = 100;  // the output stage's, 1 to 1000 V
};

struct EmulatorOptions {
  device::Capabilities caps;
  std::string record_path;  // JSON lines, one per delivered pulse (empty: none)
  EmulatorSkin skin;
};

// Opens "emu" or a port at `baud`.  A port is opened exclusively: an advisory lock
// (flock) that every stimctl takes, and TIOCEXCL against other programs; a port already
// held is a runtime failure naming it.  A path that is not a terminal is bad input.  backend:
// "auto" (by the port, as above), "libserialport" or "posix".
std::unique_ptr<Transport> open_transport(const std::string& port, int baud,
                                          const EmulatorOptions& emu,
                                          const std::string& backend = "auto");

// Serial ports known to libserialport: "name\tdescription" each.
std::vector<std::string> list_serial_ports();

// The monotonic clock (used by the emulators and the host).
std::int64_t monotonic_ns();
std::uint64_t monotonic_us();

}  // namespace tp::host
