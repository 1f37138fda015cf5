#pragma once
// Relume's binary files (image fans, a project's kept daylight solution): little-endian values
// written into a byte buffer, read back with every read bounds-checked (a truncated or damaged
// file is a relume::Error naming the file and the part, never a crash), a CRC-32 at the end, and
// an atomic write (a temporary file of this process's own, synced and renamed into place).
#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

namespace relume {

class ByteWriter {
 public:
  std::vector<uint8_t> bytes;
  void raw(const void* p, size_t n) {
    bytes.insert(bytes.end(), static_cast<const uint8_t*>(p), static_cast<const uint8_t*>(p) + n);
  }
  void u32(uint32_t v);
  void u64(uint64_t v);
  void f64(double v);
  void text(const std::string& s);
  // A count and the elements' bytes as they are in memory (readers check the element size in the
  // file's header: a file is read back by a build with the same layout).
  template <class T>
  void array(const std::vector<T>& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    u64(v.size());
    raw(v.data(), v.size() * sizeof(T));
  }
  // Appends the CRC-32 of everything written so far (ByteReader::sealed checks it).
  void seal();
};

class ByteReader {
 public:
  // `name` is the file the bytes came from, for the messages.
  ByteReader(const std::vector<uint8_t>& bytes, std::string name, size_t pos = 0)
      : b_(bytes), name_(std::move(name)), pos(pos) {}
  const std::string& name() const { return name_; }
  const std::vector<uint8_t>& bytes() const { return b_; }
  // Throws "the file is truncated" unless n more bytes are there (`what`: the part being read).
  void need(size_t n, const char* what) const;
  uint32_t u32(const char* what);
  uint64_t u64(const char* what);
  double f64(const char* what);  // a finite number, else an error
  std::string text(const char* what, size_t maxLength = 4096);
  // An array ByteWriter::array wrote: at most `maxCount` elements.
  template <class T>
  std::vector<T> array(const char* what, size_t maxCount) {
    static_assert(std::is_trivially_copyable_v<T>);
    const uint64_t n = u64(what);
    if (n > maxCount) fail(what, "holds more elements than it can (damaged)");
    need(size_t(n) * sizeof(T), what);
    std::vector<T> v(static_cast<size_t>(n));
    if (n) std::memcpy(v.data(), b_.data() + pos, size_t(n) * sizeof(T));
    pos += size_t(n) * sizeof(T);
    return v;
  }
  // Whether the last 4 bytes are the CRC-32 of the rest.
  bool sealed() const;
  // The reader is at the CRC (all read): else "bytes after its end".
  void expectEnd() const;
  [[noreturn]] void fail(const std::string& part, const std::string& problem) const;

 private:
  const std::vector<uint8_t>& b_;
  std::string name_;

 public:
  size_t pos;
};

// The whole file; throws relume::Error naming it when it cannot be read.
std::vector<uint8_t> readFileBytes(const std::string& path);
// Written whole or not at all: an existing file is replaced only once the new one is on disk.
void writeFileAtomically(const std::string& path, const std::vector<uint8_t>& bytes);

}  // namespace relume
