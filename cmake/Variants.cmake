# A variant is the engine built against one directory of hook files (solutions/, assignments/, a
# submission, a seeded mistake). The framework is compiled once; a variant compiles only its hook
# files and links.
file(STRINGS ${CMAKE_CURRENT_LIST_DIR}/hook_files.txt GPL_HOOK_FILES REGEX "^[^#]")
set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${CMAKE_CURRENT_LIST_DIR}/hook_files.txt)

# gpl_add_variant(NAME DIR): the object library gpl_hooks_NAME and the runner gpl-run-NAME.
function(gpl_add_variant name dir)
  set(sources)
  foreach(file IN LISTS GPL_HOOK_FILES)
    list(APPEND sources ${dir}/${file})
  endforeach()
  add_library(gpl_hooks_${name} OBJECT ${sources})
  target_link_libraries(gpl_hooks_${name} PUBLIC gpl::framework)

  add_executable(gpl-run-${name} $<TARGET_OBJECTS:gpl_run_main>)
  target_link_libraries(gpl-run-${name} PRIVATE gpl_hooks_${name} gpl::framework CLI11::CLI11)
endfunction()
