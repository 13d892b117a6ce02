// One binary serialiser for the ground floor (checkpoints, replicated
// records): trivially copyable values and vectors of them, with a length
// prefix, and a 64-bit FNV-1a checksum over the bytes.  Reading past the end
// or a length that cannot fit throws std::runtime_error.  Also the hashes
// that go with them.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace lem {

inline std::uint64_t fnv1a(const char* data, std::size_t n,
                           std::uint64_t h = 1469598103934665603ULL) {
  for (std::size_t i = 0; i < n; ++i)
    h = (h ^ static_cast<unsigned char>(data[i])) * 1099511628211ULL;
  return h;
}

/// splitmix64's finaliser: a well-mixed 64-bit hash of one word (seeded
/// per-bond random numbers, order-free checksums).
inline std::uint64_t mix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

class ByteWriter {
 public:
  template <class T>
  void pod(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    raw(&v, sizeof(T));
  }
  template <class T>
  void vec(const std::vector<T>& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    pod(static_cast<std::uint64_t>(v.size()));
    raw(v.data(), v.size() * sizeof(T));
  }
  void str(const std::string& s) { vec(std::vector<char>(s.begin(), s.end())); }
  void raw(const void* p, std::size_t n) {
    bytes.insert(bytes.end(), static_cast<const char*>(p), static_cast<const char*>(p) + n);
  }
  std::vector<char> bytes;
};

class ByteReader {
 public:
  /// Reads bytes[0, end).
  ByteReader(const std::vector<char>& bytes, std::size_t end) : b_(bytes), end_(end) {}
  template <class T>
  void pod(T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    raw(&v, sizeof(T));
  }
  template <class T>
  void vec(std::vector<T>& v) {
    std::uint64_t n = 0;
    pod(n);
    if (n > (end_ - pos_) / std::max<std::size_t>(1, sizeof(T)))
      throw std::runtime_error("length beyond the end");
    v.resize(n);
    raw(v.data(), n * sizeof(T));
  }
  void str(std::string& s) {
    std::vector<char> c;
    vec(c);
    s.assign(c.begin(), c.end());
  }
  void raw(void* p, std::size_t n) {
    if (n > end_ - pos_) throw std::runtime_error("short");
    if (n > 0) std::memcpy(p, b_.data() + pos_, n);  // p may be null then (an empty vector)
    pos_ += n;
  }
  bool at_end() const { return pos_ == end_; }

 private:
  const std::vector<char>& b_;
  std::size_t end_, pos_ = 0;
};

}  // namespace lem
