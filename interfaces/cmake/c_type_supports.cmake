# Generate only what rclpy uses (the C type supports and the Python bindings) unless
# WITH_CPP_TYPESUPPORT is ON: the C++ generators, found through the message packages this one
# depends on, would otherwise double the build. Include this file before
# rosidl_generate_interfaces().
option(WITH_CPP_TYPESUPPORT "Also generate the C++ headers and type supports" OFF)
if(NOT WITH_CPP_TYPESUPPORT)
  list(FILTER AMENT_EXTENSIONS_rosidl_generate_idl_interfaces EXCLUDE REGEX "_cpp:")
  message(STATUS "Generating the C and Python type supports only (WITH_CPP_TYPESUPPORT=OFF)")
endif()
