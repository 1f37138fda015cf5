#pragma once
// A fuzz input holding several files: two little-endian 16-bit lengths, then the first file, the
// second, and the rest as the third (absent when empty).
#include <cstddef>
#include <cstdint>
#include <string>

namespace relume::fuzz {
struct Parts {
  std::string a, b, c;
  bool hasC = false;
};
inline Parts split3(const uint8_t* data, size_t size) {
  Parts p;
  if (size < 4) return p;
  size_t la = size_t(data[0]) | size_t(data[1]) << 8, lb = size_t(data[2]) | size_t(data[3]) << 8;
  const char* d = reinterpret_cast<const char*>(data + 4);
  size_t left = size - 4;
  la = la < left ? la : left;
  p.a.assign(d, la);
  d += la;
  left -= la;
  lb = lb < left ? lb : left;
  p.b.assign(d, lb);
  d += lb;
  left -= lb;
  p.c.assign(d, left);
  p.hasC = left > 0;
  return p;
}
}  // namespace relume::fuzz
