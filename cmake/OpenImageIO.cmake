# caustix_find_openimageio(): find OpenImageIO and make its imported target
# usable. Debian's OpenImageIO config names /usr/include/opencv4, which exists
# only with libopencv-dev; drop that entry rather than pull in OpenCV.
# Imported targets are per directory, so every directory that links
# OpenImageIO calls this.
macro(caustix_find_openimageio)
  find_package(OpenImageIO REQUIRED)
  foreach(_prop INTERFACE_INCLUDE_DIRECTORIES INTERFACE_SYSTEM_INCLUDE_DIRECTORIES)
    get_target_property(_dirs OpenImageIO::OpenImageIO ${_prop})
    if(_dirs)
      list(FILTER _dirs EXCLUDE REGEX "opencv4")
      set_target_properties(OpenImageIO::OpenImageIO PROPERTIES ${_prop} "${_dirs}")
    endif()
  endforeach()
endmacro()
