# Installs the build tree into a scratch prefix, then configures, builds and
# runs tests/package_consumer against it: checks the CMake package export
# (every exported target links and works, odomcal::plugin links alone, every
# installed header compiles alone and with all the others; the consumers
# write their files into WORK_DIR).
set(prefix "${WORK_DIR}/prefix")
file(REMOVE_RECURSE "${WORK_DIR}")
foreach(step
    "install;${CMAKE_COMMAND};--install;${BUILD_DIR};--prefix;${prefix}"
    "configure;${CMAKE_COMMAND};-S;${SOURCE_DIR};-B;${WORK_DIR}/build;-DCMAKE_PREFIX_PATH=${prefix}"
    "build;${CMAKE_COMMAND};--build;${WORK_DIR}/build;--parallel;2"
    "run;${WORK_DIR}/build/consumer;${WORK_DIR}"
    "run plugin_only;${WORK_DIR}/build/plugin_only;${WORK_DIR}")
  list(POP_FRONT step name)
  execute_process(COMMAND ${step} RESULT_VARIABLE result OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT result EQUAL 0)
    message(FATAL_ERROR "package consumer: ${name} failed (${result}):\n${out}\n${err}")
  endif()
endforeach()
