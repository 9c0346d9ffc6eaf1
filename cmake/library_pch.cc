// The object whose compilation makes the libraries' shared precompiled header
// (zbrdf_use_library_pch in cmake/ZbrdfLibrary.cmake). It has no code of its own.
