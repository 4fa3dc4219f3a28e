#pragma once
// The checks the programs' command-line parser makes on a flag's value, for the values a
// request gets without it (from the Python module, or a C++ caller): in the parser's words.

#include <optional>
#include <string>

namespace tp {

// "FLAG: 300 outside [1, 256]", as an integer flag's range is refused (cli::add_integer).
void check_whole(const std::string& flag, long value, long lo, long hi);

// "FLAG: non-finite number 'nan'" ('inf', '-inf'), as a flag's number is refused.
void check_finite(const std::string& flag, std::optional<double> value);

}  // namespace tp
