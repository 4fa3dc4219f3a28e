#pragma once
// The shared entry point of every program: parses the command line, runs the body, and
// owns the try/catch, the one-line error message and the exit status, so that no program
// repeats them.
//
//   0  success; --help and --version print to stdout
//   1  runtime failure (I/O error, device lost, solver failure)
//   2  bad input or usage
//
// Output discipline: a body builds its whole result before writing to stdout, or, for
// streamed output, validates everything first, so a refusal leaves stdout empty.

#include <cstdint>
#include <functional>
#include <string>
#include <string_view>

#include <CLI/CLI.hpp>

namespace tp::cli {

// Adds --version to `app`, parses argv into it and runs `body`; returns the exit status
// for main().  Declare the program as CLI::App app{"description", "name"}.
int run(CLI::App& app, int argc, char** argv, const std::function<void()>& body);

// An integer option in [lo, hi], its whole text parsed by tp::parse_integer: a value
// outside, a fraction or junk is bad input naming the text as given ("--population:
// 99999999999999999999 outside [1, 10000]").  (CLI11's own conversion clamps a 64-bit
// overflow to the largest value, reads 010 as octal and 0x10 as hex.)  Its type name is N.
CLI::Option* add_integer(CLI::App& app, const std::string& name, int& target,
                         const std::string& help, int lo, int hi);
CLI::Option* add_integer(CLI::App& app, const std::string& name, long& target,
                         const std::string& help, long lo, long hi);

// A seed: any whole number from 0 to 2^64 - 1 (18446744073709551615), exactly; a sign or
// anything beyond is bad input naming the text and the range (CLI11 would take -1 as
// 2^64 - 1 and clamp 2^64 to it).  Its type name is S.
CLI::Option* add_seed(CLI::App& app, const std::string& name, std::uint64_t& target,
                      const std::string& help);

// An emulator's skin (docs/skin.md): `skin_flag` FILE into path and `compliance_flag` V (as
// typed, parsed by the caller) into compliance; `record` names where the measurements go
// ("the record", "--record"), `only` prefixes the skin's help ("Emulator only: ", or "").
void add_skin_flags(CLI::App& app, const std::string& skin_flag,
                    const std::string& compliance_flag, std::string& path,
                    std::string& compliance, const std::string& record,
                    const std::string& only);

// Writes a string to stdout and flushes; an I/O failure is a runtime failure.  With
// --output FILE (add_output_option), the text goes to FILE instead, which is written whole
// when the program succeeds and left as it was when it fails (core/files.hpp).
void write_stdout(std::string_view text);

// Adds --output FILE to a program that writes one document.  The file is created (as a
// temporary beside it) before the body runs, so that an unwritable place is refused first.
void add_output_option(CLI::App& app);

}  // namespace tp::cli
