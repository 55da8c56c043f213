# test_robot_description_is_current: regenerate the description from the URDF and compare it with
# the one the build compiled (a stale build or a hand-edited header fails).
execute_process(COMMAND ${PYTHON} ${GENERATOR} ${URDF} ${FRESH} RESULT_VARIABLE status)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "generator failed on ${URDF}")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${FRESH} ${BUILT} RESULT_VARIABLE differ)
if(NOT differ EQUAL 0)
  message(FATAL_ERROR "${BUILT} is not what ${GENERATOR} makes of ${URDF}: rebuild")
endif()
message(STATUS "robot description is current")
