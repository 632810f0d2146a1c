# A variant is the engine built against one directory of hook files (solutions/, assignments/, a
# submission, a seeded mistake). The framework is compiled once; a variant compiles only its hook
# files and links.
file(STRINGS ${CMAKE_CURRENT_LIST_DIR}/hook_files.txt GPL_HOOK_FILES REGEX "^[^#]")
set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${CMAKE_CURRENT_LIST_DIR}/hook_files.txt)

# gpl_add_variant(NAME DIR [REUSE OTHER...] [COMPILE_OPTIONS OPTION...]): the library
# gpl_hooks_NAME (link it to get the variant's hook objects) and the runner gpl-run-NAME. Each hook
# file is an object library of its own; with REUSE, a file whose text equals that of one of the
# variants OTHER is not compiled again but taken from it (a seeded mistake changes one file: it
# compiles one file; a submission compiles only the files its student changed).
#
# Hook files are always compiled with assertions on (-UNDEBUG undoes the -DNDEBUG of a Release
# build): a student's assert() fires, and the grader names it, in every preset, in the batch, on
# Gradescope and in the student release alike, so a submission scores the same whatever built it.
#
# The engine's headers (Eigen's among them) are parsed once for every hook file of every variant: a
# precompiled header, made by gpl_hook_pch with the hook files' own flags. It takes a hook file
# from 1.5 s to 0.5 s of compiling (the seeded mistakes, the submissions, a student's edit).
function(gpl_hook_pch_target)
  if(TARGET gpl_hook_pch)
    return()
  endif()
  file(CONFIGURE OUTPUT ${CMAKE_BINARY_DIR}/gpl_hook_pch.cpp CONTENT "// the precompiled header of the hook files\n")
  add_library(gpl_hook_pch OBJECT ${CMAKE_BINARY_DIR}/gpl_hook_pch.cpp)
  target_link_libraries(gpl_hook_pch PRIVATE gpl::framework)
  target_compile_options(gpl_hook_pch PRIVATE -UNDEBUG)
  target_precompile_headers(gpl_hook_pch PRIVATE <gpl/engine.h> <gpl/hooks.h>)
endfunction()

function(gpl_add_variant name dir)
  cmake_parse_arguments(PARSE_ARGV 2 arg "" "" "REUSE;COMPILE_OPTIONS")
  gpl_hook_pch_target()
  set(objects)
  foreach(file IN LISTS GPL_HOOK_FILES)
    string(MAKE_C_IDENTIFIER ${file} id)
    set(reused OFF)
    if(arg_REUSE)
      file(READ ${dir}/${file} mine)
    endif()
    foreach(other IN LISTS arg_REUSE)
      file(READ ${GPL_VARIANT_DIR_${other}}/${file} theirs)
      if(mine STREQUAL theirs)
        list(APPEND objects $<TARGET_OBJECTS:gpl_hookfile_${other}_${id}>)
        set(reused ON)
        break()
      endif()
    endforeach()
    if(reused)
      continue()
    endif()
    add_library(gpl_hookfile_${name}_${id} OBJECT ${dir}/${file})
    target_link_libraries(gpl_hookfile_${name}_${id} PRIVATE gpl::framework)
    target_compile_options(gpl_hookfile_${name}_${id} PRIVATE -UNDEBUG)
    target_precompile_headers(gpl_hookfile_${name}_${id} REUSE_FROM gpl_hook_pch)
    if(arg_COMPILE_OPTIONS)
      target_compile_options(gpl_hookfile_${name}_${id} PRIVATE ${arg_COMPILE_OPTIONS})
    endif()
    list(APPEND objects $<TARGET_OBJECTS:gpl_hookfile_${name}_${id}>)
  endforeach()
  set(GPL_VARIANT_DIR_${name} ${dir} CACHE INTERNAL "hook directory of variant ${name}")
  gpl_add_compiled_variant(${name} ${objects})
endfunction()

# gpl_add_compiled_variant(NAME OBJECT...): the library gpl_hooks_NAME and the runner gpl-run-NAME
# from hook objects compiled already: those of gpl_add_variant, or the reference engine of a student
# release written with ./lab release --reference-demo (object files without their source).
function(gpl_add_compiled_variant name)
  add_library(gpl_hooks_${name} INTERFACE)
  target_sources(gpl_hooks_${name} INTERFACE ${ARGN})
  target_link_libraries(gpl_hooks_${name} INTERFACE gpl::framework)

  add_executable(gpl-run-${name} $<TARGET_OBJECTS:gpl_run_main>)
  target_link_libraries(gpl-run-${name} PRIVATE gpl_hooks_${name} gpl::framework)
  if(GPL_CORE_TESTS_ONLY)
    set_target_properties(gpl-run-${name} PROPERTIES EXCLUDE_FROM_ALL ON)
  endif()
endfunction()
