// raw-frames: talks to a stimulator on a pseudo-terminal frame by frame, as a hostile or
// confused host would, for the protocol-level safety tests.  Reads commands from stdin:
//
//   send SEQ TYPE [HEX]   encode and write one frame (TYPE as a number, payload in hex),
//                         wait up to 300 ms for its ack; prints "SEQ RESULT BODYHEX" or
//                         "SEQ timeout"
//   raw HEX               write these bytes as they are
//   sleep MS              wait
//
//   raw-frames /dev/pts/5 < script
#include <chrono>
#include <cstdio>
#include <iostream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "device/frame.hpp"
#include "host/transport.hpp"

namespace {

std::vector<std::uint8_t> from_hex(const std::string& h) {
  std::vector<std::uint8_t> b;
  for (std::size_t i = 0; i + 1 < h.size(); i += 2)
    b.push_back(static_cast<std::uint8_t>(std::stoul(h.substr(i, 2), nullptr, 16)));
  return b;
}

std::string to_hex(const std::vector<std::uint8_t>& b) {
  std::string s;
  char buf[3];
  for (std::uint8_t x : b) {
    std::snprintf(buf, sizeof buf, "%02x", x);
    s += buf;
  }
  return s.empty() ? "-" : s;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: raw-frames PORT < script\n");
    return 2;
  }
  try {
    auto t = tp::host::open_transport(argv[1], 115200, {}, "posix");
    tp::device::FrameDecoder d;
    std::string line;
    while (std::getline(std::cin, line)) {
      std::istringstream in(line);
      std::string cmd;
      in >> cmd;
      if (cmd == "sleep") {
        int ms = 0;
        in >> ms;
        std::this_thread::sleep_for(std::chrono::milliseconds(ms));
      } else if (cmd == "raw") {
        std::string hex;
        in >> hex;
        const auto b = from_hex(hex);
        t->write(b.data(), b.size());
      } else if (cmd == "send") {
        unsigned seq = 0, type = 0;
        std::string hex;
        in >> seq >> type >> hex;
        std::vector<std::uint8_t> bytes;
        tp::device::encode_frame(tp::device::Frame{static_cast<std::uint8_t>(seq),
                                                   static_cast<std::uint8_t>(type), from_hex(hex)},
                                 bytes);
        t->write(bytes.data(), bytes.size());
        const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(300);
        bool got = false;
        std::uint8_t buf[256];
        while (!got && std::chrono::steady_clock::now() < deadline) {
          const std::size_t n = t->read(buf, sizeof buf, 20);
          for (std::size_t i = 0; i < n && !got; ++i) {
            if (!d.push(buf[i]) || d.frame().seq != seq || d.frame().payload.size() < 2) continue;
            const auto& p = d.frame().payload;
            std::printf("%u %u %s\n", seq, p[1], to_hex({p.begin() + 2, p.end()}).c_str());
            got = true;
          }
        }
        if (!got) std::printf("%u timeout\n", seq);
        std::fflush(stdout);
      } else if (!cmd.empty()) {
        std::fprintf(stderr, "raw-frames: unknown command '%s'\n", cmd.c_str());
        return 2;
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "raw-frames: %s\n", e.what());
    return 1;
  }
  return 0;
}
