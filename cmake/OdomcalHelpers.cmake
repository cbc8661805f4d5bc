# -Wall -Wextra (and -Wpedantic for libraries) on odomcal's own targets,
# -Werror with ODOMCAL_WARNINGS_AS_ERRORS.
function(odomcal_target_warnings name)
  target_compile_options(${name} PRIVATE -Wall -Wextra ${ARGN})
  if(ODOMCAL_WARNINGS_AS_ERRORS)
    target_compile_options(${name} PRIVATE -Werror)
  endif()
endfunction()

# odomcal_add_library(NAME [EXPORT_NAME name] SOURCES ... HEADERS ...
#                     PUBLIC_LIBS ... PRIVATE_LIBS ...)
# A library of a top-level folder, aliased odomcal::NAME, installed and
# exported as odomcal::NAME, or as odomcal::<EXPORT_NAME> when given (then
# that alias exists in the build tree too).
function(odomcal_add_library name)
  cmake_parse_arguments(ARG "" "EXPORT_NAME" "SOURCES;HEADERS;PUBLIC_LIBS;PRIVATE_LIBS" ${ARGN})
  add_library(${name} ${ARG_SOURCES} ${ARG_HEADERS})
  add_library(odomcal::${name} ALIAS ${name})
  if(ARG_EXPORT_NAME)
    set_target_properties(${name} PROPERTIES EXPORT_NAME ${ARG_EXPORT_NAME})
    add_library(odomcal::${ARG_EXPORT_NAME} ALIAS ${name})
  endif()
  target_compile_features(${name} PUBLIC cxx_std_17)
  odomcal_target_warnings(${name} -Wpedantic)
  target_include_directories(${name} PUBLIC
    $<BUILD_INTERFACE:${PROJECT_BINARY_DIR}/include>
    $<INSTALL_INTERFACE:include>)
  target_link_libraries(${name} PUBLIC ${ARG_PUBLIC_LIBS} PRIVATE ${ARG_PRIVATE_LIBS})
  set_target_properties(${name} PROPERTIES POSITION_INDEPENDENT_CODE ON)
  file(RELATIVE_PATH folder ${PROJECT_SOURCE_DIR} ${CMAKE_CURRENT_SOURCE_DIR})
  install(TARGETS ${name} EXPORT odomcalTargets
          ARCHIVE DESTINATION lib LIBRARY DESTINATION lib)
  install(FILES ${ARG_HEADERS} DESTINATION include/odomcal/${folder})
endfunction()

# odomcal_add_test(NAME SOURCES ... LIBS ... [LABELS ...] [FIXTURES_REQUIRED ...]
#                  [COST seconds])
# One gtest binary per module; tests are discovered individually by ctest.
# FIXTURES_REQUIRED: ctest fixtures (FIXTURES_SETUP tests) every test needs.
# COST: ctest starts costlier tests first, so on a fresh checkout (no
# recorded times) the minutes-long ones do not start last under -j.
function(odomcal_add_test name)
  cmake_parse_arguments(ARG "" "COST" "SOURCES;LIBS;LABELS;FIXTURES_REQUIRED" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  odomcal_target_warnings(${name})
  target_link_libraries(${name} PRIVATE ${ARG_LIBS} GTest::gtest GTest::gtest_main)
  if(NOT ARG_LABELS)
    set(ARG_LABELS unit)
  endif()
  set(properties LABELS "${ARG_LABELS}")
  if(ARG_FIXTURES_REQUIRED)
    list(APPEND properties FIXTURES_REQUIRED "${ARG_FIXTURES_REQUIRED}")
  endif()
  if(ARG_COST)
    list(APPEND properties COST "${ARG_COST}")
  endif()
  gtest_discover_tests(${name}
    WORKING_DIRECTORY ${PROJECT_BINARY_DIR}
    PROPERTIES ${properties}
    DISCOVERY_TIMEOUT 60)
endfunction()
