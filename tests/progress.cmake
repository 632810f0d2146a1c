# What a student sees part way through the course: the worksheets' "Before you start" checks, run
# against variants with the earlier worksheets done, and the accuracy study with its hooks open.
# For each worksheet N the variant progress_worksheetN holds the reference's hook files of the
# worksheets before N and the stubs of the others (tests/command_line/worksheet_progress.py): the
# engine of a student who opens worksheet N. Every file equals one of solutions/ or assignments/, so
# these variants compile nothing; they only link.
set(gpl_progress_script ${CMAKE_CURRENT_SOURCE_DIR}/command_line/worksheet_progress.py)
file(GLOB gpl_worksheet_files CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/worksheets/[0-9][0-9]-*.md)
set(gpl_progress_inputs ${gpl_progress_script} ${gpl_worksheet_files})
foreach(file IN LISTS GPL_HOOK_FILES)
  list(APPEND gpl_progress_inputs ${PROJECT_SOURCE_DIR}/solutions/${file} ${PROJECT_SOURCE_DIR}/assignments/${file})
endforeach()
set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${gpl_progress_inputs})
execute_process(
  COMMAND ${Python3_EXECUTABLE} ${gpl_progress_script} write ${CMAKE_BINARY_DIR}/progress
  OUTPUT_VARIABLE gpl_progress_worksheets OUTPUT_STRIP_TRAILING_WHITESPACE
  RESULT_VARIABLE gpl_progress_result ERROR_VARIABLE gpl_progress_error)
if(NOT gpl_progress_result EQUAL 0)
  message(FATAL_ERROR "could not write the hook directories of the worksheets' starts: ${gpl_progress_error}")
endif()
string(REPLACE "\n" ";" gpl_progress_worksheets "${gpl_progress_worksheets}")

set(gpl_progress_env)
foreach(worksheet IN LISTS gpl_progress_worksheets)
  gpl_add_variant(progress_worksheet${worksheet} ${CMAKE_BINARY_DIR}/progress/worksheet${worksheet} REUSE solutions assignments)
  list(APPEND gpl_progress_env "GPL_RUN_WORKSHEET${worksheet}=$<TARGET_FILE:gpl-run-progress_worksheet${worksheet}>")
endforeach()

# Each worksheet's "Before you start": the scene its bullet runs lists exactly the hooks the bullet
# quotes as not implemented, and the summary says what else the bullet says it does.
add_test(NAME command_line.worksheets_before_you_start COMMAND ${Python3_EXECUTABLE} -m unittest -v test_worksheets
         WORKING_DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}/command_line)
set_tests_properties(command_line.worksheets_before_you_start PROPERTIES TIMEOUT 300 ENVIRONMENT "${gpl_progress_env}")

# The accuracy study with the Verlet hooks still stubs (a student before worksheet 2) names them
# first and skips the two Verlet integrators; with the reference it measures all five.
add_test(NAME study.accuracy_program_skips_open_hooks
         COMMAND ${Python3_EXECUTABLE} -m unittest -v test_accuracy_study.WithStubs
         WORKING_DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}/command_line)
add_test(NAME study.accuracy_program_measures_everything
         COMMAND ${Python3_EXECUTABLE} -m unittest -v test_accuracy_study.WithSolutions
         WORKING_DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}/command_line)
set_tests_properties(study.accuracy_program_skips_open_hooks study.accuracy_program_measures_everything PROPERTIES
  TIMEOUT 600 ENVIRONMENT "GPL_BENCH_ASSIGNMENTS=$<TARGET_FILE:gpl-bench-assignments>;GPL_BENCH_SOLUTIONS=$<TARGET_FILE:gpl-bench-solutions>")
