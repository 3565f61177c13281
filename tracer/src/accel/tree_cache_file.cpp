#include "accel/tree_cache_file.hpp"

#include <fmt/format.h>
#include <xxhash.h>

#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cstring>
#include <memory>
#include <new>
#include <optional>
#include <type_traits>
#include <vector>

#include "nodetrace/base/huge_pages.hpp"

namespace nodetrace::tracer {

namespace {

// Version 1: the layout described in tree_cache_file.hpp.
constexpr std::uint32_t kTreeCacheFormatVersion = 1;
constexpr char kMagic[8] = {'N', 'T', 'T', 'R', 'E', 'E', 'C', '\0'};

// Appends values and arrays of plain values as their bytes.
class ByteAppender {
 public:
  template <class T>
  void put(const T& value) {
    static_assert(std::is_trivially_copyable_v<T>);
    bytes_.append(reinterpret_cast<const char*>(&value), sizeof value);
  }
  template <class T>
  void put_array(const std::vector<T>& values) {
    static_assert(std::is_trivially_copyable_v<T>);
    put(std::uint64_t{values.size()});
    bytes_.append(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
  }
  void put_text(std::string_view text) {
    put(std::uint32_t(text.size()));
    bytes_.append(text);
  }
  std::string& bytes() { return bytes_; }

 private:
  std::string bytes_;
};

// Reads what ByteAppender wrote from a file, straight into the values and
// arrays (one pread per array: no copy of the whole file), refusing to read
// past `end` and hashing what it reads when given a hash state.
class ByteReader {
 public:
  ByteReader(int fd, std::uint64_t begin, std::uint64_t end, XXH3_state_t* hash = nullptr)
      : fd_(fd), offset_(begin), end_(end), hash_(hash) {}
  template <class T>
  T get(const char* what) {
    static_assert(std::is_trivially_copyable_v<T>);
    T value;
    read_into(&value, sizeof value, what);
    return value;
  }
  template <class T>
  std::vector<T> get_array(const char* what) {
    const auto count = get<std::uint64_t>(what);
    if (count > remaining() / sizeof(T)) {
      throw DamagedTreeFile(fmt::format("{} of {} elements runs past the end of the file", what, count));
    }
    std::vector<T> values;
    base::reserve_on_huge_pages(values, count);
    values.resize(count);
    read_into(values.data(), count * sizeof(T), what);
    return values;
  }
  std::string get_bytes(std::size_t size, const char* what) {
    std::string bytes(std::min<std::uint64_t>(size, remaining()), '\0');
    read_into(bytes.data(), size, what);
    return bytes;
  }
  std::uint64_t remaining() const { return end_ - offset_; }
  std::uint64_t offset() const { return offset_; }

 private:
  void read_into(void* destination, std::size_t size, const char* what) {
    if (size > remaining()) {
      throw DamagedTreeFile(fmt::format("truncated: {} bytes, the {} needs {} more", end_, what, size - remaining()));
    }
    auto* bytes = static_cast<char*>(destination);
    for (std::size_t done = 0; done < size;) {
      const ssize_t got = ::pread(fd_, bytes + done, size - done, off_t(offset_ + done));
      if (got < 0 && errno == EINTR) continue;
      if (got <= 0) {
        throw DamagedTreeFile(got == 0 ? std::string("shorter than it was a moment ago")
                                       : fmt::format("cannot be read: {}", std::strerror(errno)));
      }
      done += std::size_t(got);
    }
    if (hash_) XXH3_128bits_update(hash_, bytes, size);
    offset_ += size;
  }
  int fd_;
  std::uint64_t offset_, end_;
  XXH3_state_t* hash_;
};

void put_stats(ByteAppender& out, const KdTreeStats& s) {
  for (const std::uint64_t count : {s.nodes, s.interior, s.leaves, s.empty_leaves, s.primitive_references}) {
    out.put(count);
  }
  out.put_array(s.nodes_per_level);
  out.put(s.depth);
  out.put(s.depth_limit);
  for (const double figure : {s.mean_leaf_size, s.mean_nonempty_leaf_size, s.sah_cost}) out.put(figure);
}

KdTreeStats get_stats(ByteReader& in) {
  KdTreeStats s;
  for (std::uint64_t* count : {&s.nodes, &s.interior, &s.leaves, &s.empty_leaves, &s.primitive_references}) {
    *count = in.get<std::uint64_t>("figures");
  }
  s.nodes_per_level = in.get_array<std::uint64_t>("nodes per level");
  s.depth = in.get<std::uint32_t>("figures");
  s.depth_limit = in.get<int>("figures");
  for (double* figure : {&s.mean_leaf_size, &s.mean_nonempty_leaf_size, &s.sah_cost}) {
    *figure = in.get<double>("figures");
  }
  return s;
}

void check(bool holds, std::string_view what) {
  if (!holds) throw DamagedTreeFile(fmt::format("inconsistent structure: {}", what));
}

std::string hex_of(const XXH128_hash_t& hash) { return fmt::format("{:016x}{:016x}", hash.high64, hash.low64); }

}  // namespace

// The one place that reads and restores the trees' members (a friend of
// KdTree, Bvh and AccelerationStructure).
struct TreeCacheCodec {
  static void put_kdtree(ByteAppender& out, const KdTree& tree) {
    out.put_array(tree.nodes_);
    out.put_array(tree.primitives_);
  }

  static KdTree get_kdtree(ByteReader& in, const Bounds& bounds, KdTreeStats stats, std::uint64_t triangles) {
    KdTree tree;
    tree.nodes_ = in.get_array<KdNode>("kd-tree nodes");
    tree.primitives_ = in.get_array<std::uint32_t>("leaf lists");
    tree.bounds_ = bounds;
    tree.stats_ = std::move(stats);
    // Cheap checks that no traversal can index outside the arrays.
    const auto node_count = tree.nodes_.size();
    check(tree.stats_.nodes == node_count, "node count");
    for (const KdNode& node : tree.nodes_) {
      if (node.is_leaf()) {
        check(node.first <= tree.primitives_.size() && node.count <= tree.primitives_.size() - node.first,
              "leaf list range");
      } else {
        check(node.axis < 3 && node.left < node_count && node.right < node_count, "child index");
      }
    }
    for (const auto primitive : tree.primitives_) check(primitive < triangles, "triangle index");
    return tree;
  }

  static void put_bvh(ByteAppender& out, const Bvh& bvh) {
    out.put(std::uint32_t{bvh.arity_});
    out.put(std::uint8_t{bvh.compressed_});
    out.put_array(bvh.nodes_);
    out.put_array(bvh.children_);
    out.put_array(bvh.exact_boxes_);
    out.put_array(bvh.quantizations_);
    out.put_array(bvh.primitives_);
  }

  static Bvh get_bvh(ByteReader& in, unsigned arity, bool compressed, const Bounds& bounds, KdTreeStats stats,
                     std::uint64_t triangles) {
    Bvh bvh;
    bvh.arity_ = in.get<std::uint32_t>("arity");
    bvh.compressed_ = in.get<std::uint8_t>("compression flag") != 0;
    bvh.nodes_ = in.get_array<BvhNode>("BVH nodes");
    bvh.children_ = in.get_array<BvhChild>("BVH children");
    bvh.exact_boxes_ = in.get_array<Bounds>("exact child boxes");
    bvh.quantizations_ = in.get_array<BvhQuantization>("quantizations");
    bvh.primitives_ = in.get_array<std::uint32_t>("leaf lists");
    check(bvh.arity_ == arity && bvh.compressed_ == compressed, "node format");
    bvh.bounds_ = bounds;
    bvh.stats_ = std::move(stats);
    const auto node_count = bvh.nodes_.size();
    check(bvh.stats_.nodes == node_count, "node count");
    for (const BvhNode& node : bvh.nodes_) {
      check(node.first_child <= bvh.children_.size() && node.child_count <= bvh.children_.size() - node.first_child,
            "child range");
    }
    for (const BvhChild& child : bvh.children_) {
      if (child.is_leaf()) {
        check(child.index <= bvh.primitives_.size() && child.count <= bvh.primitives_.size() - child.index,
              "leaf range");
      } else {
        check(child.index < node_count, "child index");
      }
    }
    for (const auto primitive : bvh.primitives_) check(primitive < triangles, "triangle index");
    return bvh;
  }

  static AccelerationStructure make(AccelKind kind, std::variant<KdTree, Bvh> tree) {
    return {kind, std::move(tree)};
  }

  static KdTreeStats& stats_of(AccelerationStructure& structure) {
    return std::visit([](auto& tree) -> KdTreeStats& { return tree.stats_; }, structure.tree_);
  }
};

std::string tree_cache_key(std::span<const Triangle> triangles, AccelKind kind, const AccelBuildOptions& options) {
  ByteAppender key;
  key.put(kTreeCacheFormatVersion);
  key.put_text(NODETRACE_VERSION);
  // The byte order and the sizes of what the file holds as bytes.
  key.put(std::uint8_t{std::endian::native == std::endian::little});
  for (const std::uint32_t size : {sizeof(Triangle), sizeof(Bounds), sizeof(KdNode), sizeof(BvhNode),
                                   sizeof(BvhChild), sizeof(BvhQuantization)}) {
    key.put(size);
  }
  key.put(kind);
  // Every field that shapes a tree (KdBuildOptions::threads does not).
  const KdBuildOptions& kd = options.kdtree;
  key.put(kd.traversal_cost);
  key.put(kd.intersection_cost);
  key.put(kd.empty_bonus);
  key.put(kd.max_depth);
  key.put(kd.leaf_size);
  const BvhBuildOptions& bvh = options.bvh;
  key.put(bvh.traversal_cost);
  key.put(bvh.intersection_cost);
  key.put(bvh.max_leaf_size);
  key.put(bvh.bins);
  key.put(std::uint64_t{triangles.size()});
  const XXH128_hash_t hash = XXH3_128bits(triangles.data(), triangles.size_bytes());
  key.put(hash.high64);
  key.put(hash.low64);
  return std::move(key.bytes());
}

std::string tree_cache_file_name(std::string_view key) {
  return fmt::format("nodetrace-{}.tree", hex_of(XXH3_128bits(key.data(), key.size())));
}

std::string encode_tree_cache_file(const AccelerationStructure& structure, std::string_view key) {
  ByteAppender payload;
  payload.put(structure.bounds());
  put_stats(payload, structure.stats());
  if (const KdTree* tree = structure.kdtree()) {
    TreeCacheCodec::put_kdtree(payload, *tree);
  } else {
    TreeCacheCodec::put_bvh(payload, *structure.bvh());
  }
  ByteAppender file;
  file.bytes().append(kMagic, sizeof kMagic);
  file.put(kTreeCacheFormatVersion);
  file.put_text(key);
  file.put(std::uint64_t{payload.bytes().size()});
  const XXH128_hash_t checksum = XXH3_128bits(payload.bytes().data(), payload.bytes().size());
  file.put(checksum.high64);
  file.put(checksum.low64);
  file.bytes() += payload.bytes();
  return std::move(file.bytes());
}

AccelerationStructure read_tree_cache_file(int fd, std::uint64_t file_size, std::string_view key, AccelKind kind,
                                           std::uint64_t triangle_count) {
  ByteReader in(fd, 0, file_size);
  if (in.get_bytes(sizeof kMagic, "magic") != std::string_view(kMagic, sizeof kMagic)) {
    throw DamagedTreeFile("not a tree cache file (bad magic)");
  }
  if (const auto version = in.get<std::uint32_t>("format version"); version != kTreeCacheFormatVersion) {
    throw DamagedTreeFile(fmt::format("file format version {}, expected {}", version, kTreeCacheFormatVersion));
  }
  const auto key_size = in.get<std::uint32_t>("key length");
  if (key_size != key.size() || in.get_bytes(key_size, "key") != key) {
    throw DamagedTreeFile("made for another tracer version, other build options or other triangles (key differs)");
  }
  const auto payload_size = in.get<std::uint64_t>("payload length");
  XXH128_hash_t checksum;
  checksum.high64 = in.get<std::uint64_t>("checksum");
  checksum.low64 = in.get<std::uint64_t>("checksum");
  if (payload_size != in.remaining()) {
    throw DamagedTreeFile(fmt::format("{}: {} bytes of payload, the header says {}",
                                      payload_size > in.remaining() ? "truncated" : "too long", in.remaining(),
                                      payload_size));
  }
  // The payload is hashed as it is read; nothing read is returned unless
  // the hash is the checksum (array lengths are checked against the file's
  // size before anything is allocated).
  const std::unique_ptr<XXH3_state_t, decltype(&XXH3_freeState)> hash(XXH3_createState(), &XXH3_freeState);
  if (!hash || XXH3_128bits_reset(hash.get()) != XXH_OK) throw std::bad_alloc();
  ByteReader payload(fd, in.offset(), file_size, hash.get());
  const auto bounds = payload.get<Bounds>("bounds");
  KdTreeStats stats = get_stats(payload);
  std::optional<AccelerationStructure> structure;
  if (kind == AccelKind::KdTree) {
    structure = TreeCacheCodec::make(kind, TreeCacheCodec::get_kdtree(payload, bounds, std::move(stats),
                                                                     triangle_count));
  } else {
    structure = TreeCacheCodec::make(kind, TreeCacheCodec::get_bvh(payload, accel_arity(kind),
                                                                  kind == AccelKind::CwBvh8, bounds,
                                                                  std::move(stats), triangle_count));
  }
  if (payload.remaining() != 0) throw DamagedTreeFile(fmt::format("{} bytes after the structure", payload.remaining()));
  if (!XXH128_isEqual(XXH3_128bits_digest(hash.get()), checksum)) {
    throw DamagedTreeFile("the payload's checksum differs (the file is damaged)");
  }
  return std::move(*structure);
}

void set_load_times(AccelerationStructure& structure, double wall_seconds, double cpu_seconds) {
  KdTreeStats& stats = TreeCacheCodec::stats_of(structure);
  stats.loaded = true;
  stats.build_seconds = wall_seconds;
  stats.build_cpu_seconds = cpu_seconds;
}

}  // namespace nodetrace::tracer
