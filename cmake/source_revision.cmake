# MESOCAP_SOURCE_REVISION: the git commit the build was configured at ("unknown" outside a git
# tree), "+dirty" when tracked files differed then. Provenance records it. The configure step
# reruns when HEAD moves, so the value follows commits without a manual reconfigure.
find_package(Git QUIET)
set(MESOCAP_SOURCE_REVISION "unknown")
if(GIT_FOUND AND EXISTS "${PROJECT_SOURCE_DIR}/.git")
  execute_process(COMMAND ${GIT_EXECUTABLE} rev-parse --short=12 HEAD WORKING_DIRECTORY ${PROJECT_SOURCE_DIR}
                  OUTPUT_VARIABLE revision OUTPUT_STRIP_TRAILING_WHITESPACE RESULT_VARIABLE failed ERROR_QUIET)
  if(NOT failed)
    execute_process(COMMAND ${GIT_EXECUTABLE} diff --quiet HEAD -- WORKING_DIRECTORY ${PROJECT_SOURCE_DIR}
                    RESULT_VARIABLE dirty ERROR_QUIET)
    set(MESOCAP_SOURCE_REVISION "${revision}")
    if(dirty)
      string(APPEND MESOCAP_SOURCE_REVISION "+dirty")
    endif()
    execute_process(COMMAND ${GIT_EXECUTABLE} rev-parse --git-path HEAD WORKING_DIRECTORY ${PROJECT_SOURCE_DIR}
                    OUTPUT_VARIABLE head_file OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
    execute_process(COMMAND ${GIT_EXECUTABLE} symbolic-ref -q HEAD WORKING_DIRECTORY ${PROJECT_SOURCE_DIR}
                    OUTPUT_VARIABLE ref OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
    cmake_path(ABSOLUTE_PATH head_file BASE_DIRECTORY ${PROJECT_SOURCE_DIR})
    set(watch "${head_file}")
    if(ref)
      execute_process(COMMAND ${GIT_EXECUTABLE} rev-parse --git-path ${ref} WORKING_DIRECTORY ${PROJECT_SOURCE_DIR}
                      OUTPUT_VARIABLE ref_file OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
      cmake_path(ABSOLUTE_PATH ref_file BASE_DIRECTORY ${PROJECT_SOURCE_DIR})
      if(EXISTS "${ref_file}")
        list(APPEND watch "${ref_file}")
      endif()
    endif()
    set_property(DIRECTORY ${PROJECT_SOURCE_DIR} APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${watch})
  endif()
endif()
