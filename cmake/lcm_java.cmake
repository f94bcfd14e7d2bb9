# Java classes of the project's LCM types, in one jar, so that lcm-spy (LCM's Java traffic
# viewer) decodes our channels: put the jar on CLASSPATH before starting lcm-spy.
#   lcm-gen --java  ->  javac against the lcm wheel's lcm.jar  ->  f16mmae_lcmtypes.jar
# Optional: built when a JDK (javac, jar) and lcm.jar are found; the configure step says which
# it is. Installed into the Python package as f16mmae/java/f16mmae_lcmtypes.jar.
find_package(Java COMPONENTS Development QUIET)
find_file(F16MMAE_LCM_JAR lcm.jar
  PATHS "${lcm_DIR}/../../../share/java" "${lcm_DIR}/../../../../share/java"
  NO_DEFAULT_PATH)
if(Java_JAVAC_EXECUTABLE AND Java_JAR_EXECUTABLE AND F16MMAE_LCM_JAR)
  set(_java_dir "${CMAKE_CURRENT_BINARY_DIR}/lcmgen/java")
  set(F16MMAE_LCM_TYPES_JAR "${CMAKE_CURRENT_BINARY_DIR}/f16mmae_lcmtypes.jar")
  set(_java_sources "")
  foreach(_f ${F16MMAE_LCM_FILES})
    get_filename_component(_t ${_f} NAME_WE)
    list(APPEND _java_sources "${_java_dir}/src/f16mmae/${_t}.java")
  endforeach()
  add_custom_command(
    OUTPUT ${F16MMAE_LCM_TYPES_JAR}
    COMMAND ${CMAKE_COMMAND} -E rm -rf "${_java_dir}"
    COMMAND ${CMAKE_COMMAND} -E make_directory "${_java_dir}/src" "${_java_dir}/classes"
    COMMAND lcm-gen --java --jpath "${_java_dir}/src" ${F16MMAE_LCM_FILES}
    COMMAND ${Java_JAVAC_EXECUTABLE} -nowarn -cp "${F16MMAE_LCM_JAR}" -d "${_java_dir}/classes" ${_java_sources}
    COMMAND ${Java_JAR_EXECUTABLE} cf ${F16MMAE_LCM_TYPES_JAR} -C "${_java_dir}/classes" .
    DEPENDS ${F16MMAE_LCM_FILES}
    COMMENT "lcm-gen --java, javac, jar: ${F16MMAE_LCM_TYPES_JAR}"
    VERBATIM)
  add_custom_target(f16mmae_lcmtypes_java ALL DEPENDS ${F16MMAE_LCM_TYPES_JAR})
  message(STATUS "f16mmae: lcm-spy types will be built (${Java_JAVAC_EXECUTABLE}, ${F16MMAE_LCM_JAR})")
else()
  message(STATUS "f16mmae: no JDK or no lcm.jar: the lcm-spy types jar is not built (optional)")
endif()
