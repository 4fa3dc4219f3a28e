# A Catch2 test's name must not hold ';': catch_discover_tests splits names at it, so the
# CTest tests it makes run no test at all.  Run as
#   cmake -DTESTS=<exe>,<exe>... -P check_test_names.cmake
# It fails naming the first such test, in one line.
string(REPLACE "," ";" executables "${TESTS}")
foreach(exe IN LISTS executables)
  # Catch2 v2 exits with the number of tests listed: the names, not the status, count.
  execute_process(COMMAND "${exe}" --list-test-names-only OUTPUT_VARIABLE names)
  string(REPLACE ";" "<semicolon>" names "${names}")
  string(REGEX MATCHALL "[^\n]+" lines "${names}")
  set(count 0)
  foreach(name IN LISTS lines)
    math(EXPR count "${count} + 1")
    if(name MATCHES "<semicolon>")
      string(REPLACE "<semicolon>" ";" name "${name}")
      get_filename_component(base "${exe}" NAME)
      message(FATAL_ERROR "${base}: test name holds ';' (CTest would split it): \"${name}\"")
    endif()
  endforeach()
  if(count EQUAL 0)
    message(FATAL_ERROR "${exe} lists no tests")
  endif()
endforeach()
