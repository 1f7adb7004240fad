#include "snapshot.h"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <bit>
#include <fstream>
#include <iterator>

namespace epi {

namespace {

constexpr char kMagic[8] = {'E', 'P', 'I', 'S', 'N', 'A', 'P', '1'};
// kUnreachedStayBlack: ReconstructSettings::blend_unreached_near_edges off (older files: on).
enum Flag : uint32_t { kCentreLines = 1, kAntialias = 2, kComplexFilter = 4, kFill = 8, kUnreachedStayBlack = 16, kKnownFlags = 31 };

static_assert(std::endian::native == std::endian::little, "snapshots are written little-endian");

template <typename T>
void put(std::string& out, const T& v) {
  out.append(reinterpret_cast<const char*>(&v), sizeof(T));
}
template <typename T>
void put_all(std::string& out, const std::vector<T>& v) {
  out.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
}

// Reads from a byte string; every read names what it reads, so a short file says where it ends.
class Reader {
 public:
  Reader(const std::string& bytes, const std::string& file) : bytes_(bytes), file_(file) {}
  template <typename T>
  T get(const char* what) {
    T v;
    take(&v, sizeof(T), what);
    return v;
  }
  template <typename T>
  void get_all(std::vector<T>& v, size_t count, const char* what) {
    v.resize(count);
    take(v.data(), count * sizeof(T), what);
  }
  size_t left() const { return bytes_.size() - pos_; }
  [[noreturn]] void fail(const std::string& problem) const { throw SnapshotError(file_ + ": " + problem); }

 private:
  void take(void* dst, size_t n, const char* what) {
    if (left() < n) fail(std::string("truncated: the file ends inside the ") + what);
    std::memcpy(dst, bytes_.data() + pos_, n);
    pos_ += n;
  }
  const std::string& bytes_;
  const std::string& file_;
  size_t pos_ = 0;
};

std::string read_file(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw SnapshotError(file + ": cannot open for reading");
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw SnapshotError(file + ": read error");
  return bytes;
}

}  // namespace

std::string snapshot_bytes(const Snapshot& s) {
  const int w = s.epi.width, h = s.epi.height;
  if (w != s.masks.width || h != s.masks.height) throw std::invalid_argument("the EPI and its masks differ in size");
  std::string out;
  out.append(kMagic, sizeof(kMagic));
  put(out, uint32_t(w));
  put(out, uint32_t(h));
  const uint32_t flags = (s.masks.centre_lines ? uint32_t(kCentreLines) : 0u) | (s.settings.antialias ? uint32_t(kAntialias) : 0u) |
                         (s.settings.complex_filter ? uint32_t(kComplexFilter) : 0u) | (s.settings.fill ? uint32_t(kFill) : 0u) |
                         (s.settings.blend_unreached_near_edges ? 0u : uint32_t(kUnreachedStayBlack));
  put(out, flags);
  put_all(out, s.epi.edge);
  put_all(out, s.epi.color);
  put_all(out, s.masks.top);
  put_all(out, s.masks.left);
  if (s.masks.centre_lines) put_all(out, s.masks.centre_h), put_all(out, s.masks.centre_v);
  put(out, uint64_t(s.segments.size()));
  for (const Segment& g : s.segments) put(out, g.x0), put(out, g.y0), put(out, g.x1), put(out, g.y1);
  return out;
}

void save_snapshot(const Snapshot& s, const std::string& file) {
  const std::string out = snapshot_bytes(s);
  const std::string temporary = file + ".part";
  {
    std::ofstream o(temporary, std::ios::binary | std::ios::trunc);
    if (!o) throw SnapshotError(file + ": cannot open for writing");
    o.write(out.data(), std::streamsize(out.size()));
    o.close();
    if (!o) {
      std::remove(temporary.c_str());
      throw SnapshotError(file + ": write error");
    }
  }
  if (std::rename(temporary.c_str(), file.c_str()) != 0) {
    std::remove(temporary.c_str());
    throw SnapshotError(file + ": cannot write");
  }
}

bool is_snapshot_file(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  char head[sizeof(kMagic)] = {};
  return in.read(head, sizeof(head)) && std::memcmp(head, kMagic, sizeof(kMagic)) == 0;
}

Snapshot load_snapshot(const std::string& file) {
  const std::string bytes = read_file(file);
  Reader r(bytes, file);
  char magic[sizeof(kMagic)];
  for (char& c : magic) c = r.get<char>("header");
  if (std::memcmp(magic, kMagic, sizeof(kMagic)) != 0) r.fail("not an EPI snapshot (no EPISNAP1 header)");
  const uint32_t w = r.get<uint32_t>("header"), h = r.get<uint32_t>("header"), flags = r.get<uint32_t>("header");
  if (w < 1 || h < 1 || w > kMaxSnapshotSize || h > kMaxSnapshotSize)
    r.fail("image size " + std::to_string(w) + "x" + std::to_string(h) + " is not in [1, " +
           std::to_string(kMaxSnapshotSize) + "]");
  if (flags & ~uint32_t(kKnownFlags)) r.fail("unknown flags " + std::to_string(flags));
  Snapshot s;
  s.epi = EpiImage(int(w), int(h));
  s.masks = BoundaryMasks(int(w), int(h), flags & kCentreLines);
  s.settings.antialias = flags & kAntialias;
  s.settings.complex_filter = flags & kComplexFilter;
  s.settings.fill = flags & kFill;
  s.settings.blend_unreached_near_edges = !(flags & kUnreachedStayBlack);
  const size_t pixels = size_t(w) * h, cells = size_t(w + 1) * (h + 1);
  r.get_all(s.epi.edge, pixels, "edge plane");
  r.get_all(s.epi.color, pixels, "colour plane");
  r.get_all(s.masks.top, cells, "top masks");
  r.get_all(s.masks.left, cells, "left masks");
  if (s.masks.centre_lines) r.get_all(s.masks.centre_h, cells, "centre masks"), r.get_all(s.masks.centre_v, cells, "centre masks");
  const uint64_t count = r.get<uint64_t>("segment count");
  if (count > r.left() / 32)
    r.fail("truncated: segment count " + std::to_string(count) + " needs more than the " + std::to_string(r.left()) + " bytes left");
  s.segments.resize(size_t(count));
  for (Segment& g : s.segments) {
    g = {r.get<double>("segments"), r.get<double>("segments"), r.get<double>("segments"), r.get<double>("segments")};
    if (!std::isfinite(g.x0) || !std::isfinite(g.y0) || !std::isfinite(g.x1) || !std::isfinite(g.y1))
      r.fail("segment " + std::to_string(&g - s.segments.data()) + " is not finite");
  }
  if (r.left() != 0) r.fail(std::to_string(r.left()) + " unexpected bytes after the segments");
  return s;
}

}  // namespace epi
