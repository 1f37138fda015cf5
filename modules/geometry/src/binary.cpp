#include "relume/geometry/binary.h"

#include <fcntl.h>
#include <unistd.h>
#include <zlib.h>

#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "relume/geometry/error.h"

namespace relume {

void ByteWriter::u32(uint32_t v) {
  for (int k = 0; k < 4; ++k) bytes.push_back(uint8_t(v >> (8 * k)));
}
void ByteWriter::u64(uint64_t v) {
  for (int k = 0; k < 8; ++k) bytes.push_back(uint8_t(v >> (8 * k)));
}
void ByteWriter::f64(double v) {
  uint64_t u;
  std::memcpy(&u, &v, 8);
  u64(u);
}
void ByteWriter::text(const std::string& s) {
  u32(uint32_t(s.size()));
  raw(s.data(), s.size());
}
void ByteWriter::seal() { u32(uint32_t(crc32_z(0L, bytes.data(), bytes.size()))); }

void ByteReader::fail(const std::string& part, const std::string& problem) const { throw Error(name_, part, problem); }

void ByteReader::need(size_t n, const char* what) const {
  if (pos > b_.size() || n > b_.size() - pos)
    fail(what, "the file is truncated (it ends inside its " + std::string(what) + ")");
}
uint32_t ByteReader::u32(const char* what) {
  need(4, what);
  uint32_t v = 0;
  for (int k = 0; k < 4; ++k) v |= uint32_t(b_[pos + size_t(k)]) << (8 * k);
  pos += 4;
  return v;
}
uint64_t ByteReader::u64(const char* what) {
  need(8, what);
  uint64_t v = 0;
  for (int k = 0; k < 8; ++k) v |= uint64_t(b_[pos + size_t(k)]) << (8 * k);
  pos += 8;
  return v;
}
double ByteReader::f64(const char* what) {
  const uint64_t u = u64(what);
  double v;
  std::memcpy(&v, &u, 8);
  if (!std::isfinite(v)) fail(what, "holds a value that is not a finite number");
  return v;
}
std::string ByteReader::text(const char* what, size_t maxLength) {
  const uint32_t n = u32(what);
  if (n > maxLength) fail(what, "holds a text longer than it can (damaged)");
  need(n, what);
  std::string s(reinterpret_cast<const char*>(b_.data() + pos), n);
  pos += n;
  return s;
}
bool ByteReader::sealed() const {
  if (b_.size() < 4) return false;
  const size_t e = b_.size() - 4;
  const uint32_t stored = uint32_t(b_[e]) | uint32_t(b_[e + 1]) << 8 | uint32_t(b_[e + 2]) << 16 | uint32_t(b_[e + 3]) << 24;
  return uint32_t(crc32_z(0L, b_.data(), e)) == stored;
}
void ByteReader::expectEnd() const {
  need(4, "checksum");
  if (pos + 4 != b_.size()) fail("", "the file has bytes after its end (damaged)");
}

std::vector<uint8_t> readFileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path, "", "cannot be read");
  std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw Error(path, "", "cannot be read");
  return bytes;
}

void writeFileAtomically(const std::string& path, const std::vector<uint8_t>& bytes) {
  // A temporary name of this process's own (two writers never share one), renamed into place.
  static std::atomic<unsigned> serial{0};
  const std::string tmp = path + ".part" + std::to_string(::getpid()) + "." + std::to_string(serial++);
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (fd < 0) throw Error(path, "", std::string("cannot be written: ") + std::strerror(errno));
  auto abandon = [&](int e, const char* what) {
    std::remove(tmp.c_str());
    throw Error(path, "", std::string("cannot be written: ") + what + std::strerror(e));
  };
  size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t k = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (k < 0) {
      if (errno == EINTR) continue;
      const int e = errno;
      ::close(fd);
      abandon(e, "");
    }
    done += size_t(k);
  }
  if (::fsync(fd) != 0) {
    const int e = errno;
    ::close(fd);
    abandon(e, "the disk refused to keep it: ");
  }
  if (::close(fd) != 0) abandon(errno, "the disk refused to keep it: ");
  if (::rename(tmp.c_str(), path.c_str()) != 0) abandon(errno, "");
  // The rename itself kept: the folder's entry synced.
  const std::string dir = std::filesystem::path(path).parent_path().string();
  const int dfd = ::open(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dfd >= 0) {
    ::fsync(dfd);
    ::close(dfd);
  }
}

}  // namespace relume
