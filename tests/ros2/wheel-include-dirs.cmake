# Included into the build of an interface package by build-interfaces.sh (CMAKE_PROJECT_INCLUDE).
#
# The ROS 2 wheels were built in a manylinux container: their exported CMake targets
# `<pkg>::<pkg>__rosidl_generator_py` name that container's Python and NumPy headers
# (/opt/python/cp311-cp311/...), which do not exist here, and CMake refuses to generate with
# an imported target naming a missing include directory. At the end of the configure step
# (after every find_package, including those rosidl_generate_interfaces does), each such
# directory of an imported target is replaced by this machine's (MCM_PYTHON_INCLUDE,
# MCM_NUMPY_INCLUDE, given by the script); any other missing include directory of the wheels
# stops the build, naming it.

if(NOT MCM_PYTHON_INCLUDE OR NOT MCM_NUMPY_INCLUDE)
  message(FATAL_ERROR "MCM_PYTHON_INCLUDE and MCM_NUMPY_INCLUDE must be set (build-interfaces.sh does)")
endif()

function(mcm_fix_wheel_include_dirs)
  get_directory_property(targets DIRECTORY "${CMAKE_SOURCE_DIR}" IMPORTED_TARGETS)
  foreach(target IN LISTS targets)
    get_target_property(dirs ${target} INTERFACE_INCLUDE_DIRECTORIES)
    if(NOT dirs OR NOT dirs MATCHES "/opt/python/")
      continue()
    endif()
    set(fixed)
    foreach(dir IN LISTS dirs)
      if(EXISTS "${dir}" OR NOT dir MATCHES "^/opt/python/")
        list(APPEND fixed "${dir}")
      elseif(dir MATCHES "/site-packages/numpy/(_core/)?include$")
        list(APPEND fixed "${MCM_NUMPY_INCLUDE}")
      elseif(dir MATCHES "/include/python3\\.[0-9]+$")
        list(APPEND fixed "${MCM_PYTHON_INCLUDE}")
      else()
        message(FATAL_ERROR "${target}: include directory ${dir} of the wheels' build machine has no known counterpart here")
      endif()
    endforeach()
    list(REMOVE_DUPLICATES fixed)
    set_target_properties(${target} PROPERTIES INTERFACE_INCLUDE_DIRECTORIES "${fixed}")
  endforeach()
endfunction()

cmake_language(DEFER DIRECTORY "${CMAKE_SOURCE_DIR}" CALL mcm_fix_wheel_include_dirs)
