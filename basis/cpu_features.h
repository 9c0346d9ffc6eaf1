// What the CPU the program runs on can do, for the inner loops that pick an instruction set when
// the program starts (the build itself targets baseline x86-64, so that it runs anywhere).
#pragma once

namespace zbrdf {

// True if the CPU has AVX2 (x86-64 with GCC or Clang; false elsewhere). Asked once.
bool CpuHasAvx2();
// True if the CPU has AVX2 and FMA3, the fused multiply-adds (every AVX2 CPU made so far has
// both, but they are separate CPUID bits).
bool CpuHasAvx2Fma();
// True if the CPU has F16C, the float <-> half conversions (and AVX, whose registers they use).
bool CpuHasF16c();

}  // namespace zbrdf
