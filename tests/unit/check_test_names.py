#!/usr/bin/env python3
"""A Catch2 test's name must hold no ';', '[' or ']': catch_discover_tests passes the names
through CMake lists, which split at ';' and do not split inside square brackets, so such a
name makes CTest tests that run nothing, or swallows every test listed after it.  Run as
    check_test_names.py EXE [EXE ...]
It fails naming the first such test, in one line."""
import os
import subprocess
import sys

for exe in sys.argv[1:]:
    # Catch2 v2 exits with the number of tests listed: the names, not the status, count.
    names = subprocess.run([exe, "--list-test-names-only"], capture_output=True,
                           text=True).stdout.splitlines()
    names = [n for n in names if n.strip()]
    if not names:
        sys.exit(f"check_test_names: {exe} lists no tests")
    for n in names:
        bad = [c for c in ";[]" if c in n]
        if bad:
            sys.exit(f"check_test_names: {os.path.basename(exe)}: test name holds "
                     f"'{bad[0]}' (CTest would lose it or the tests after it): \"{n}\"")
print(f"check_test_names: {len(sys.argv) - 1} programs, no name holds ';', '[' or ']'")
