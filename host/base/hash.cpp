// SPDX-License-Identifier: Apache-2.0
#include <smoothforce/base/hash.h>

#include <xxhash.h>

#include <cstdio>
#include <fstream>
#include <vector>

#include <smoothforce/base/error.h>

namespace sf {

uint64_t hashBytes(const void* data, size_t size, uint64_t seed) { return XXH64(data, size, seed); }

uint64_t hashFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open for reading");
  XXH64_state_t* st = XXH64_createState();
  XXH64_reset(st, 0);
  std::vector<char> buf(1 << 16);
  while (in) {
    in.read(buf.data(), static_cast<std::streamsize>(buf.size()));
    if (in.gcount() > 0) XXH64_update(st, buf.data(), static_cast<size_t>(in.gcount()));
  }
  const uint64_t h = XXH64_digest(st);
  XXH64_freeState(st);
  return h;
}

std::string hexHash(uint64_t h) {
  char s[17];
  std::snprintf(s, sizeof s, "%016llx", static_cast<unsigned long long>(h));
  return s;
}

}  // namespace sf
