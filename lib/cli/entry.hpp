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

#include <functional>
#include <string>
#include <string_view>

#include <CLI/CLI.hpp>

namespace tp::cli {

// Adds --version to `app`, parses argv into it and runs `body`; returns the exit status
// for main().  Declare the program as CLI::App app{"description", "name"}.
int run(CLI::App& app, int argc, char** argv, const std::function<void()>& body);

// Writes a string to stdout and flushes; an I/O failure is a runtime failure.  With
// --output FILE (add_output_option), the text goes to FILE instead, which is written whole
// when the program succeeds and left as it was when it fails (io/files.hpp).
void write_stdout(std::string_view text);

// Adds --output FILE to a program that writes one document.  The file is created (as a
// temporary beside it) before the body runs, so that an unwritable place is refused first.
void add_output_option(CLI::App& app);

}  // namespace tp::cli
