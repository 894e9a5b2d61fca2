# Modules are bound lazily (core/module_loader.h): every symbol must resolve when the module is
# linked, so none can be missing mid-run. Not in sanitizer builds, whose modules take the
# sanitizer runtime from the executable.
function(mesocap_module_resolves_all_symbols target)
  if(MESOCAP_SANITIZE STREQUAL "" AND NOT MESOCAP_FUZZ)
    target_link_options(${target} PRIVATE -Wl,-z,defs)
  endif()
endfunction()

# mesocap_test(NAME stage/foo_test SOURCES foo_test.cc LIBS lib... [LABELS ...] [TIMEOUT s])
# Builds one GoogleTest binary and registers it in ctest under the name given.
function(mesocap_test)
  cmake_parse_arguments(T "" "NAME;TIMEOUT" "SOURCES;LIBS;LABELS" ${ARGN})
  if(NOT MESOCAP_BUILD_TESTS)
    return()
  endif()
  string(REPLACE "/" "_" target "${T_NAME}")
  add_executable(${target} ${T_SOURCES})
  target_link_libraries(${target} PRIVATE ${T_LIBS} mesocap_testing GTest::gtest GTest::gtest_main)
  # Tests that read checked-in data (photographs, corpora) find it from the source tree.
  target_compile_definitions(${target} PRIVATE MESOCAP_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
  add_test(NAME ${T_NAME} COMMAND ${target})
  if(NOT T_TIMEOUT)
    set(T_TIMEOUT 300)
  endif()
  set_tests_properties(${T_NAME} PROPERTIES TIMEOUT ${T_TIMEOUT} LABELS "${T_LABELS}"
                       ENVIRONMENT "MESOCAP_BIN=$<TARGET_FILE:mesocap>;MESOCAP_SOURCE_DIR=${PROJECT_SOURCE_DIR}")
endfunction()
