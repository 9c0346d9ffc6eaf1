// Compiled only to produce the precompiled common headers that the libraries and the tests reuse
// (cmake/ZbrdfLibrary.cmake, zbrdf_precompile_common_headers). Defines nothing.
