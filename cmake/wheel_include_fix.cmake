# Injected with -DCMAKE_PROJECT_INCLUDE by the Makefile.
#
# The ROS 2 Jazzy wheels on PyPI export CMake targets (*__rosidl_generator_py and friends)
# whose INTERFACE_INCLUDE_DIRECTORIES name the Python and NumPy include directories of the
# machine that built the wheels (/opt/python/cp311-cp311/...). CMake refuses such targets
# ("includes non-existent path"). At the end of configure, every imported target of the
# project's directories gets those entries replaced by this machine's Python and NumPy
# include directories. The venv itself is left untouched.
find_package(Python3 REQUIRED COMPONENTS Interpreter Development.Module NumPy)

function(tethersim_fix_wheel_includes)
  get_property(_targets DIRECTORY "${CMAKE_SOURCE_DIR}" PROPERTY IMPORTED_TARGETS)
  foreach(_target IN LISTS _targets)
    get_target_property(_dirs ${_target} INTERFACE_INCLUDE_DIRECTORIES)
    if(NOT _dirs)
      continue()
    endif()
    set(_fixed "")
    set(_changed FALSE)
    foreach(_dir IN LISTS _dirs)
      if(_dir MATCHES "^/opt/python/.*numpy")
        list(APPEND _fixed "${Python3_NumPy_INCLUDE_DIRS}")
        set(_changed TRUE)
      elseif(_dir MATCHES "^/opt/python/")
        list(APPEND _fixed "${Python3_INCLUDE_DIRS}")
        set(_changed TRUE)
      else()
        list(APPEND _fixed "${_dir}")
      endif()
    endforeach()
    if(_changed)
      list(REMOVE_DUPLICATES _fixed)
      set_target_properties(${_target} PROPERTIES INTERFACE_INCLUDE_DIRECTORIES "${_fixed}")
    endif()
  endforeach()
endfunction()

cmake_language(DEFER DIRECTORY "${CMAKE_SOURCE_DIR}" CALL tethersim_fix_wheel_includes)
