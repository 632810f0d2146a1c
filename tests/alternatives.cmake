# Correct alternatives of the hooks (tests/alternatives/*.json): each a variant that must score full marks.
# Included after the GPL_CORE_TESTS_ONLY return of tests/CMakeLists.txt, as the seeded mistakes are:
# a core-tests build has neither.

# ---- The solutions with hook files written another way, in rounds, each a hook directory -----------
file(GLOB GPL_ALTERNATIVE_SPECS CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/alternatives/*.json)
set(gpl_alternative_inputs ${GPL_ALTERNATIVE_SPECS})
foreach(file IN LISTS GPL_HOOK_FILES)
  list(APPEND gpl_alternative_inputs ${PROJECT_SOURCE_DIR}/solutions/${file})
endforeach()
set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${gpl_alternative_inputs})
execute_process(
  COMMAND ${Python3_EXECUTABLE} ${PROJECT_SOURCE_DIR}/tools/hooks.py alternatives ${CMAKE_BINARY_DIR}/alternatives
  OUTPUT_VARIABLE gpl_alternatives OUTPUT_STRIP_TRAILING_WHITESPACE
  RESULT_VARIABLE gpl_alternatives_result ERROR_VARIABLE gpl_alternatives_error)
if(NOT gpl_alternatives_result EQUAL 0)
  message(FATAL_ERROR "could not write the correct alternatives: ${gpl_alternatives_error}")
endif()
# One line per round: its name, the earliest worksheet of its hook files and its alternatives.
string(REPLACE "\n" ";" gpl_alternatives "${gpl_alternatives}")
foreach(line IN LISTS gpl_alternatives)
  string(REPLACE " " ";" line "${line}")
  list(GET line 0 round)
  gpl_add_variant(alternatives_${round} ${CMAKE_BINARY_DIR}/alternatives/${round} REUSE solutions)
  set_target_properties(gpl-run-alternatives_${round} PROPERTIES EXCLUDE_FROM_ALL ON)
  gpl_add_hooks_server(alternatives_${round})
endforeach()

# ---- Grader self-checks of the rounds: full marks on every test that can call their hooks -----------
# A hook is called by the tests of its own worksheet and of later ones (their scenes and kernels build
# on it), never by an earlier worksheet's. A round that loses points names its alternatives above the
# table; the failing tests' hooks say which of them to look at.
foreach(line IN LISTS gpl_alternatives)
  string(REPLACE " " ";" line "${line}")
  list(GET line 0 round)
  list(GET line 1 worksheet)
  list(GET line 2 names)
  string(REPLACE "," ", " names "${names}")
  add_test(NAME grader.alternatives.${round}
           COMMAND ${grade} selfcheck --checker $<TARGET_FILE:gpl-checker>
                   --hooks $<TARGET_FILE:gpl-hooks-alternatives_${round}> --expect full --from-worksheet ${worksheet}
                   --about "correct alternatives: ${names}")
  set_tests_properties(grader.alternatives.${round} PROPERTIES ENVIRONMENT "${gpl_selfcheck_env}")
endforeach()
