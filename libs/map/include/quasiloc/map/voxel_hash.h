#pragma once
// Voxel keys and a flat hash map keyed by them, for the scan fusion and the free-space carving (map_build.h).
// A key packs the three integer voxel coordinates (21 bits each, offset by 2^20) into 64 bits: +-2^20 voxels per
// axis, i.e. +-52 km at 5 cm. The map is open addressing with linear probing over one array (no node per entry):
// a ray caster looks a voxel up at every step, and std::unordered_map's chained nodes cost a cache miss each.
#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

namespace quasiloc::map
{
using VoxelKey = uint64_t;
constexpr int kVoxelKeyBits = 21;
constexpr int32_t kVoxelKeyOffset = 1 << (kVoxelKeyBits - 1);
constexpr VoxelKey kNoVoxel = ~VoxelKey(0);

/** Voxel coordinates -> key; false when a coordinate is outside the +-2^20 range. */
inline bool packVoxel(const Eigen::Vector3i& v, VoxelKey& key)
{
    VoxelKey k = 0;
    for (int a = 0; a < 3; ++a)
    {
        const int64_t c = int64_t(v[a]) + kVoxelKeyOffset;
        if (c < 0 || c >= (int64_t(1) << kVoxelKeyBits)) return false;
        k |= VoxelKey(c) << (kVoxelKeyBits * a);
    }
    key = k;
    return true;
}

inline Eigen::Vector3i unpackVoxel(VoxelKey key)
{
    const VoxelKey mask = (VoxelKey(1) << kVoxelKeyBits) - 1;
    return {int32_t((key >> 0) & mask) - kVoxelKeyOffset, int32_t((key >> kVoxelKeyBits) & mask) - kVoxelKeyOffset,
            int32_t((key >> (2 * kVoxelKeyBits)) & mask) - kVoxelKeyOffset};
}

/** The voxel holding p for cubes of `size` aligned with the origin. */
inline Eigen::Vector3i voxelOf(const Eigen::Vector3f& p, float inv_size)
{
    return {int32_t(std::floor(p.x() * inv_size)), int32_t(std::floor(p.y() * inv_size)),
            int32_t(std::floor(p.z() * inv_size))};
}

/** Open-addressing hash map VoxelKey -> V (V default-constructible). Grows at 50 % load; never shrinks. */
template <class V>
class VoxelHashMap
{
   public:
    explicit VoxelHashMap(size_t initial_capacity = 1024) { rehash(roundUp(initial_capacity)); }

    size_t size() const { return size_; }
    size_t capacity() const { return keys_.size(); }
    size_t memoryBytes() const { return keys_.size() * (sizeof(VoxelKey) + sizeof(V)); }

    /** The value of `key`, inserted default-constructed when absent. */
    V& operator[](VoxelKey key)
    {
        if (2 * (size_ + 1) > keys_.size()) rehash(2 * keys_.size());
        size_t i = slot(key);
        while (keys_[i] != kNoVoxel && keys_[i] != key) i = (i + 1) & mask_;
        if (keys_[i] == kNoVoxel)
        {
            keys_[i] = key;
            values_[i] = V();
            ++size_;
        }
        return values_[i];
    }
    V* find(VoxelKey key)
    {
        for (size_t i = slot(key);; i = (i + 1) & mask_)
        {
            if (keys_[i] == key) return &values_[i];
            if (keys_[i] == kNoVoxel) return nullptr;
        }
    }
    const V* find(VoxelKey key) const { return const_cast<VoxelHashMap*>(this)->find(key); }

    /** f(key, value&) for every entry, in slot order. */
    template <class F>
    void forEach(F&& f)
    {
        for (size_t i = 0; i < keys_.size(); ++i)
            if (keys_[i] != kNoVoxel) f(keys_[i], values_[i]);
    }
    template <class F>
    void forEach(F&& f) const
    {
        for (size_t i = 0; i < keys_.size(); ++i)
            if (keys_[i] != kNoVoxel) f(keys_[i], values_[i]);
    }

   private:
    static size_t roundUp(size_t n)
    {
        size_t c = 16;
        while (c < n) c *= 2;
        return c;
    }
    size_t slot(VoxelKey key) const
    {
        key ^= key >> 33;  // murmur3's finaliser: the packed coordinates' low bits alone cluster
        key *= 0xff51afd7ed558ccdULL;
        key ^= key >> 33;
        return size_t(key) & mask_;
    }
    void rehash(size_t capacity)
    {
        std::vector<VoxelKey> old_keys(capacity, kNoVoxel);
        std::vector<V> old_values(capacity);
        old_keys.swap(keys_);
        old_values.swap(values_);
        mask_ = capacity - 1;
        size_ = 0;
        for (size_t i = 0; i < old_keys.size(); ++i)
            if (old_keys[i] != kNoVoxel) (*this)[old_keys[i]] = std::move(old_values[i]);
    }

    std::vector<VoxelKey> keys_;
    std::vector<V> values_;
    size_t mask_ = 0, size_ = 0;
};

}  // namespace quasiloc::map
