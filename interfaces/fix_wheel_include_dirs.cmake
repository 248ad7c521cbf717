# Injected with -DCMAKE_PROJECT_INCLUDE=<this file> (runs at each project() call).
# The PyPI ros-* interface wheels were built in a manylinux container; their exported
# <pkg>::<pkg>__rosidl_generator_py targets carry that container's absolute paths
#   /opt/python/cp311-cp311/include/python3.11
#   /opt/python/cp311-cp311/lib/python3.11/site-packages/numpy/_core/include
# in INTERFACE_INCLUDE_DIRECTORIES, and CMake refuses to generate with non-existent
# include dirs on imported targets. At the end of the top-level directory we drop
# every such non-existent dir from every imported target (the package's own python
# extension already gets the real Python3/NumPy include dirs from FindPython3).
cmake_minimum_required(VERSION 3.21)  # DEFER (3.19) + IMPORTED_TARGETS (3.21)
function(_fix_wheel_include_dirs)
  get_property(_targets DIRECTORY "${CMAKE_SOURCE_DIR}" PROPERTY IMPORTED_TARGETS)
  foreach(_t IN LISTS _targets)
    get_target_property(_dirs ${_t} INTERFACE_INCLUDE_DIRECTORIES)
    if(NOT _dirs)
      continue()
    endif()
    set(_keep "")
    set(_changed FALSE)
    foreach(_d IN LISTS _dirs)
      if(_d MATCHES "^\\$<" OR IS_DIRECTORY "${_d}")
        list(APPEND _keep "${_d}")
      else()
        set(_changed TRUE)
      endif()
    endforeach()
    if(_changed)
      set_target_properties(${_t} PROPERTIES INTERFACE_INCLUDE_DIRECTORIES "${_keep}")
    endif()
  endforeach()
endfunction()
if(CMAKE_CURRENT_SOURCE_DIR STREQUAL CMAKE_SOURCE_DIR)
  cmake_language(DEFER DIRECTORY "${CMAKE_SOURCE_DIR}" CALL _fix_wheel_include_dirs)
endif()
