// A check of an OpenEXR file's headers before OpenEXR reads them, for the readers of zbrdf's
// EXR files (zonal.exr, SH and D-BRDF files).
//
// OpenEXR 3.1 allocates every header attribute at the size the file declares before reading it,
// so a corrupt or hostile file of a few KB can ask for gigabytes (found by fuzz/zonal_exr_fuzz).
// Every attribute of a real file lies inside the file; this scan rejects one that does not. It
// follows the layout of the OpenEXR file format ("OpenEXR File Layout": magic number, version
// field, then per part a header of name, type, int32 size and value, ended by an empty name;
// multi-part files end the list of headers with one more empty name) and stops quietly at
// anything else, which OpenEXR then reports itself.
#pragma once

#include <string>

namespace zbrdf {

// Throws InputError naming `what` (e.g. "zonal file x.exr") if a header attribute of the file at
// `path` declares a negative size or more bytes than the file holds, or a part declares more
// chunks (scan-line blocks or tiles) than the file has room for their 8-byte offsets (OpenEXR
// allocates that table before reading anything else). Does nothing if the file cannot be read
// or is not OpenEXR (the caller's reader says so).
void CheckExrHeaderSizes(const std::string& path, const std::string& what);

// Throws InputError naming `what` and the part unless the data window starts at (0, 0) and is
// at least one pixel: zbrdf writes its files so, and the readers' frame buffers assume it (an
// offset window makes the usual base-pointer arithmetic point outside the buffer, which is
// undefined behaviour; found by fuzz/dbrdf_file_fuzz).
void RequireWindowAtOrigin(int min_x, int min_y, int max_x, int max_y, const std::string& what,
                           const std::string& part);

}  // namespace zbrdf
