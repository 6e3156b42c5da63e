// SPDX-License-Identifier: Apache-2.0
// libFuzzer harness for the OBJ reader (readMesh on a .obj file). See fuzz_common.h.
#include "fuzz_mesh.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return sf::fuzz::fuzzMesh(data, size, ".obj");
}
