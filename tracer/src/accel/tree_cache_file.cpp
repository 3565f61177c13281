#include "accel/tree_cache_file.hpp"

#include <fmt/format.h>
#include <xxhash.h>

#include <bit>
#include <cstring>
#include <type_traits>
#include <vector>

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

// Reads what ByteAppender wrote, refusing to read past the end.
class ByteReader {
 public:
  explicit ByteReader(std::string_view bytes) : bytes_(bytes) {}
  template <class T>
  T get(const char* what) {
    static_assert(std::is_trivially_copyable_v<T>);
    T value;
    std::memcpy(&value, take(sizeof value, what), sizeof value);
    return value;
  }
  template <class T>
  std::vector<T> get_array(const char* what) {
    const auto count = get<std::uint64_t>(what);
    if (count > remaining() / sizeof(T)) {
      throw DamagedTreeFile(fmt::format("{} of {} elements runs past the end of the file", what, count));
    }
    std::vector<T> values(count);
    std::memcpy(values.data(), take(count * sizeof(T), what), count * sizeof(T));
    return values;
  }
  std::string_view get_bytes(std::size_t size, const char* what) { return {take(size, what), size}; }
  std::size_t remaining() const { return bytes_.size() - offset_; }
  std::size_t offset() const { return offset_; }

 private:
  const char* take(std::size_t size, const char* what) {
    if (size > remaining()) {
      throw DamagedTreeFile(fmt::format("truncated: {} bytes, the {} needs {} more", bytes_.size(), what,
                                        size - remaining()));
    }
    const char* start = bytes_.data() + offset_;
    offset_ += size;
    return start;
  }
  std::string_view bytes_;
  std::size_t offset_ = 0;
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
    check(node_count > 0 && tree.stats_.nodes == node_count, "node count");
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
  return fmt::format("{}-{}.tree", "nodetrace", hex_of(XXH3_128bits(key.data(), key.size())));
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

AccelerationStructure decode_tree_cache_file(std::string_view file, std::string_view key, AccelKind kind,
                                             std::uint64_t triangle_count) {
  ByteReader in(file);
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
    throw DamagedTreeFile(fmt::format("{} bytes of payload, the header says {}", in.remaining(), payload_size));
  }
  const std::string_view payload_bytes = in.get_bytes(payload_size, "payload");
  if (!XXH128_isEqual(XXH3_128bits(payload_bytes.data(), payload_bytes.size()), checksum)) {
    throw DamagedTreeFile("the payload's checksum differs (the file is damaged)");
  }
  ByteReader payload(payload_bytes);
  const auto bounds = payload.get<Bounds>("bounds");
  KdTreeStats stats = get_stats(payload);
  AccelerationStructure structure =
      kind == AccelKind::KdTree
          ? TreeCacheCodec::make(kind, TreeCacheCodec::get_kdtree(payload, bounds, std::move(stats), triangle_count))
          : TreeCacheCodec::make(kind, TreeCacheCodec::get_bvh(payload, accel_arity(kind), kind == AccelKind::CwBvh8, bounds, std::move(stats), triangle_count));
  if (payload.remaining() != 0) throw DamagedTreeFile(fmt::format("{} bytes after the structure", payload.remaining()));
  return structure;
}

void set_build_times(AccelerationStructure& structure, double wall_seconds, double cpu_seconds) {
  KdTreeStats& stats = TreeCacheCodec::stats_of(structure);
  stats.build_seconds = wall_seconds;
  stats.build_cpu_seconds = cpu_seconds;
}

}  // namespace nodetrace::tracer
