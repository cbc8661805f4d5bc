# Installs the build tree into a scratch prefix and runs the module's
# unittest with PYTHONPATH=<prefix>/<MODULE_DIR> only: the installed module
# must import and work without the build tree.
set(prefix "${WORK_DIR}/prefix")
file(REMOVE_RECURSE "${WORK_DIR}")
execute_process(COMMAND ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix}
                RESULT_VARIABLE result OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT result EQUAL 0)
  message(FATAL_ERROR "python install test: install failed (${result}):\n${out}\n${err}")
endif()
execute_process(
  COMMAND ${CMAKE_COMMAND} -E env PYTHONPATH=${prefix}/${MODULE_DIR}
          ${PYTHON} -c "import odomcal; print(odomcal.__file__)"
  RESULT_VARIABLE result OUTPUT_VARIABLE module_file ERROR_VARIABLE err)
string(FIND "${module_file}" "${prefix}/" at)
if(NOT result EQUAL 0 OR NOT at EQUAL 0)
  message(FATAL_ERROR "python install test: odomcal not imported from ${prefix} "
                      "(${result}): ${module_file}\n${err}")
endif()
execute_process(
  COMMAND ${CMAKE_COMMAND} -E env PYTHONPATH=${prefix}/${MODULE_DIR}
          ${PYTHON} ${TEST_SCRIPT}
  RESULT_VARIABLE result OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT result EQUAL 0)
  message(FATAL_ERROR "python install test: unittest failed (${result}):\n${out}\n${err}")
endif()
