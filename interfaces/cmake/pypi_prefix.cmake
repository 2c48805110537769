# Point the exported rosidl Python targets of the ROS 2 wheels at this environment.
#
# The wheels were built in manylinux containers, and their exported targets
# <package>::<package>__rosidl_generator_py list that container's Python and NumPy include
# directories (/opt/python/...), which CMake refuses as non-existent. Include this file after
# rosidl_generate_interfaces() to give every such target this environment's directories.
find_package(Python3 REQUIRED COMPONENTS Interpreter Development NumPy)
get_property(_imported_targets DIRECTORY PROPERTY IMPORTED_TARGETS)
foreach(_target IN LISTS _imported_targets)
  if(_target MATCHES "__rosidl_generator_py$")
    set_target_properties(${_target} PROPERTIES
      INTERFACE_INCLUDE_DIRECTORIES "${Python3_INCLUDE_DIRS};${Python3_NumPy_INCLUDE_DIRS}")
  endif()
endforeach()
