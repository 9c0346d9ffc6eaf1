# Debian ships OpenCV's CMake package only in the libopencv-dev meta package, which pulls in
# every module (contrib, video, dnn, ...). We need three, so we locate them directly. Not imgcodecs:
# image files go through libspng, libtiff and OpenEXR (basis/png.h; docs/design.md, section 5).
find_path(OpenCV_INCLUDE_DIR opencv2/core.hpp PATH_SUFFIXES opencv4 REQUIRED)
foreach(module core imgproc highgui)
  find_library(OpenCV_${module}_LIBRARY opencv_${module} REQUIRED)
  add_library(opencv::${module} UNKNOWN IMPORTED)
  set_target_properties(opencv::${module} PROPERTIES
    IMPORTED_LOCATION "${OpenCV_${module}_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${OpenCV_INCLUDE_DIR}")
endforeach()
