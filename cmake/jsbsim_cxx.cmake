# JSBSim's C++ API for the truth model's per-step path (bindings/bind_truth.cpp).
#
# The installed `jsbsim` Python package carries JSBSim compiled into its extension _jsbsim.so,
# which exports the C++ API (FGFDMExec, the property tree).  Its headers are not in the wheel, so
# the source distribution of the SAME release is fetched once per build tree with pip (the
# ordinary client) and only its src/ headers are used.  Linking against that _jsbsim.so makes the
# C++ truth run exactly the JSBSim code the Python truth runs.  Result: the function
# f16mmae_link_jsbsim(target) and F16MMAE_JSBSIM_VERSION (checked again at import, truth/engine.py).
execute_process(
  COMMAND "${Python_EXECUTABLE}" -c
          "import jsbsim, os; print(os.path.dirname(jsbsim.__file__), end=';'); print(jsbsim.__version__, end='')"
  OUTPUT_VARIABLE _jsb RESULT_VARIABLE _jsb_rc)
if(NOT _jsb_rc EQUAL 0)
  message(FATAL_ERROR "the truth model's C++ path needs the jsbsim Python package installed in "
                      "${Python_EXECUTABLE} (pip install 'jsbsim>=1.3,<1.4')")
endif()
list(GET _jsb 0 F16MMAE_JSBSIM_PKG_DIR)
list(GET _jsb 1 F16MMAE_JSBSIM_VERSION)
file(GLOB _jsb_lib "${F16MMAE_JSBSIM_PKG_DIR}/_jsbsim*.so")
if(NOT _jsb_lib)
  message(FATAL_ERROR "no _jsbsim*.so in ${F16MMAE_JSBSIM_PKG_DIR}")
endif()
list(GET _jsb_lib 0 F16MMAE_JSBSIM_LIBRARY)

set(_jsb_src "${CMAKE_BINARY_DIR}/_deps/jsbsim-${F16MMAE_JSBSIM_VERSION}")
if(NOT EXISTS "${_jsb_src}/src/FGFDMExec.h")
  set(_dl "${CMAKE_BINARY_DIR}/_deps/download")
  file(MAKE_DIRECTORY "${_dl}")
  execute_process(
    COMMAND "${Python_EXECUTABLE}" -m pip download --quiet --no-deps --no-binary :all:
            --no-build-isolation -d "${_dl}" "jsbsim==${F16MMAE_JSBSIM_VERSION}"
    RESULT_VARIABLE _dl_rc)
  file(GLOB _sdist "${_dl}/jsbsim-${F16MMAE_JSBSIM_VERSION}.tar.gz")
  if(NOT _dl_rc EQUAL 0 OR NOT _sdist)
    message(FATAL_ERROR "could not fetch the jsbsim ${F16MMAE_JSBSIM_VERSION} source distribution "
                        "(its headers build the truth model's C++ path)")
  endif()
  file(ARCHIVE_EXTRACT INPUT "${_sdist}" DESTINATION "${CMAKE_BINARY_DIR}/_deps" PATTERNS "*/src/*")
endif()

get_filename_component(_jsb_dir "${F16MMAE_JSBSIM_LIBRARY}" DIRECTORY)
get_filename_component(_jsb_name "${F16MMAE_JSBSIM_LIBRARY}" NAME)

# f16mmae_link_jsbsim(target): headers, the library by file name (no SONAME: the loader finds it
# through the run path, next to the installed f16mmae package or where it was at build time).
function(f16mmae_link_jsbsim target)
  target_include_directories(${target} SYSTEM PRIVATE "${_jsb_src}/src")
  target_link_directories(${target} PRIVATE "${_jsb_dir}")
  target_link_libraries(${target} PRIVATE "-l:${_jsb_name}")
  target_compile_definitions(${target} PRIVATE F16MMAE_JSBSIM_VERSION="${F16MMAE_JSBSIM_VERSION}")
  set_target_properties(${target} PROPERTIES
    BUILD_RPATH "$ORIGIN/../jsbsim;${_jsb_dir}" INSTALL_RPATH "$ORIGIN/../jsbsim;${_jsb_dir}")
endfunction()
