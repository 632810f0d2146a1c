# cmake -DDIR=FOLDER -P SanitizerReports.cmake: empties FOLDER, where the sanitizers of the graded
# self-checks write their reports (ASAN_OPTIONS/UBSAN_OPTIONS log_path, tests/CMakeLists.txt).
# With -DCHECK=ON: prints every report found there and fails if there is one.
if(NOT CHECK)
  file(REMOVE_RECURSE ${DIR})
  file(MAKE_DIRECTORY ${DIR})
  return()
endif()
file(GLOB reports ${DIR}/*)
if(NOT reports)
  message("no sanitizer report from the self-checks of the solutions and the stubs")
  return()
endif()
foreach(report IN LISTS reports)
  file(READ ${report} text)
  message("---- ${report}\n${text}")
endforeach()
list(LENGTH reports count)
message(FATAL_ERROR "${count} sanitizer report(s) from the self-checks of the solutions and the stubs (above)")
