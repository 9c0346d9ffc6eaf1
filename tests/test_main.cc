// main() of every test binary: GoogleTest's own (gtest_main), after the process setup that the
// zbrdf CLI does in RunZbrdf (basis/freed_memory.h), so that tests run the code as the CLI does.
#include <gtest/gtest.h>

#include "basis/freed_memory.h"

int main(int argc, char** argv) {
  zbrdf::KeepFreedMemoryForReuse();
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
