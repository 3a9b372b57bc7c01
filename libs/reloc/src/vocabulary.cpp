#include <quasiloc/reloc/vocabulary.h>

#include <mrpt/config/CConfigFileBase.h>
#include <quasiloc/core/error.h>
#include <quasiloc/core/ini_read.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>
#include <opencv2/core/utility.hpp>

#include "archive_io.h"
#include <random>

namespace quasiloc::reloc
{
namespace
{
const char* const kSection = "Vocabulary";
// Fixed-size tag rather than an MRPT string: a string's length prefix read from a foreign file could ask for
// gigabytes before we know the file is not ours.
constexpr char kMagic[16] = "quasiloc-vocab";
constexpr uint32_t kVersion = 1;
constexpr int64_t kMaxWords = int64_t(1) << 24;
// Below this many distance evaluations a k-means step runs on the calling thread (no pool overhead).
constexpr size_t kParallelWork = 1 << 16;

// The build's baseline x86-64 target has no popcnt instruction (__builtin_popcountll becomes a libgcc call,
// ~5x slower); clone the two hot Hamming loops for CPUs that have it, picked once at load time.
#if defined(__GNUC__) && defined(__x86_64__) && !defined(__POPCNT__)
#define QUASILOC_POPCNT_CLONES __attribute__((target_clones("popcnt", "default")))
#else
#define QUASILOC_POPCNT_CLONES
#endif

QUASILOC_POPCNT_CLONES uint32_t hammingDistance(const uint64_t* a, const uint64_t* b, int n)
{
    uint32_t d = 0;
    for (int i = 0; i < n; ++i) d += static_cast<uint32_t>(__builtin_popcountll(a[i] ^ b[i]));
    return d;
}

/** Index of the nearest of k centres (rows of n words); the first one on a tie. */
QUASILOC_POPCNT_CLONES int nearestHamming(const uint64_t* x, const uint64_t* centres, int k, int n)
{
    int best = 0;
    uint32_t best_d = UINT32_MAX;
    for (int c = 0; c < k; ++c)
    {
        const uint64_t* y = centres + size_t(c) * n;
        uint32_t d = 0;
        for (int i = 0; i < n; ++i) d += static_cast<uint32_t>(__builtin_popcountll(x[i] ^ y[i]));
        if (d < best_d) best_d = d, best = c;
    }
    return best;
}

// Float distances: eight partial sums in a fixed order, which the compiler vectorises without reassociating,
// so every clone (AVX2 or baseline SSE2) returns bit-identical distances and the tree is the same on any CPU.
#if defined(__GNUC__) && defined(__x86_64__) && !defined(__AVX2__)
#define QUASILOC_AVX2_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define QUASILOC_AVX2_CLONES
#endif

inline float squaredL2(const float* a, const float* b, int n)
{
    float acc[8] = {0, 0, 0, 0, 0, 0, 0, 0};
    int i = 0;
    for (; i + 8 <= n; i += 8)
        for (int j = 0; j < 8; ++j)
        {
            const float d = a[i + j] - b[i + j];
            acc[j] += d * d;
        }
    float sum = ((acc[0] + acc[4]) + (acc[1] + acc[5])) + ((acc[2] + acc[6]) + (acc[3] + acc[7]));
    for (; i < n; ++i)
    {
        const float d = a[i] - b[i];
        sum += d * d;
    }
    return sum;
}

QUASILOC_AVX2_CLONES float squaredL2Distance(const float* a, const float* b, int n) { return squaredL2(a, b, n); }

/** Index of the nearest of k centres (rows of n floats); the first one on a tie. */
QUASILOC_AVX2_CLONES int nearestL2(const float* x, const float* centres, int k, int n)
{
    int best = 0;
    float best_d = std::numeric_limits<float>::infinity();
    for (int c = 0; c < k; ++c)
    {
        const float d = squaredL2(x, centres + size_t(c) * n, n);
        if (d < best_d) best_d = d, best = c;
    }
    return best;
}

/** Binary descriptors as zero-padded rows of 64-bit words: Hamming distance, per-bit majority centres. */
struct HammingMetric
{
    using Elem = uint64_t;
    int n = 0;  // words per row

    double distance(const Elem* a, const Elem* b) const { return hammingDistance(a, b, n); }
    int nearest(const Elem* x, const Elem* centres, int k) const { return nearestHamming(x, centres, k, n); }
    /** Per-bit majority of the members (ties give 0). Bits are counted eight at a time: a table spreads a
     *  byte's bits over the eight byte lanes of a uint64, so one addition counts a whole byte; lanes are
     *  flushed before they can overflow. */
    void centre(const Elem* data, const std::vector<int>& members, Elem* out) const
    {
        static const std::vector<uint64_t> spread = [] {
            std::vector<uint64_t> t(256, 0);
            for (int v = 0; v < 256; ++v)
                for (int bit = 0; bit < 8; ++bit)
                    if (v & (1 << bit)) t[v] |= uint64_t(1) << (8 * bit);
            return t;
        }();
        const int bytes = 8 * n;
        std::vector<uint64_t> lanes(bytes, 0);
        std::vector<uint32_t> ones(size_t(bytes) * 8, 0);
        auto flush = [&] {
            for (int b = 0; b < bytes; ++b)
            {
                for (int bit = 0; bit < 8; ++bit) ones[b * 8 + bit] += (lanes[b] >> (8 * bit)) & 0xFF;
                lanes[b] = 0;
            }
        };
        int pending = 0;
        for (int m : members)
        {
            const auto* row = reinterpret_cast<const uint8_t*>(data + size_t(m) * n);
            for (int b = 0; b < bytes; ++b) lanes[b] += spread[row[b]];
            if (++pending == 255) flush(), pending = 0;
        }
        flush();
        auto* centre_bytes = reinterpret_cast<uint8_t*>(out);
        for (int b = 0; b < bytes; ++b)
        {
            uint8_t v = 0;
            for (int bit = 0; bit < 8; ++bit)
                if (2 * size_t(ones[b * 8 + bit]) > members.size()) v |= uint8_t(1 << bit);
            centre_bytes[b] = v;
        }
    }
};

/** Float descriptors: squared L2 distance, mean centres. */
struct L2Metric
{
    using Elem = float;
    int n = 0;  // floats per row

    double distance(const Elem* a, const Elem* b) const { return squaredL2Distance(a, b, n); }
    int nearest(const Elem* x, const Elem* centres, int k) const { return nearestL2(x, centres, k, n); }
    void centre(const Elem* data, const std::vector<int>& members, Elem* out) const
    {
        std::vector<double> sum(n, 0.0);  // double: exact enough for 10^5 members, order fixed (deterministic)
        for (int m : members)
        {
            const float* row = data + size_t(m) * n;
            for (int i = 0; i < n; ++i) sum[i] += row[i];
        }
        for (int i = 0; i < n; ++i) out[i] = static_cast<float>(sum[i] / double(members.size()));
    }
};

/** k-means++ weight: the squared distance (L2Metric's distance is already squared). */
double seedingWeight(const HammingMetric& m, const uint64_t* a, const uint64_t* b)
{
    const double d = m.distance(a, b);
    return d * d;
}
double seedingWeight(const L2Metric& m, const float* a, const float* b) { return m.distance(a, b); }

/** splitmix64: decorrelates the per-node RNG seeds derived from (seed, path in the tree). */
uint64_t mixSeed(uint64_t x)
{
    x += 0x9E3779B97F4A7C15ull;
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
    x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
    return x ^ (x >> 31);
}

template <class Elem>
struct BuildNode
{
    std::vector<Elem> centre;
    std::vector<BuildNode> children;
};

/** Hierarchical k-means over the rows of `data` (row_elements each). Every node gets its own RNG seeded
 *  from its path, and parallel loops only split work whose result does not depend on the split, so the tree
 *  is the same for any number of threads. */
template <class Metric>
class TreeBuilder
{
    using Elem = typename Metric::Elem;

   public:
    TreeBuilder(Metric metric, const std::vector<Elem>& data, const VocabularyOptions& options)
        : m_(metric), data_(data), options_(options)
    {}

    void build(BuildNode<Elem>& node, std::vector<int> members, int level, uint64_t key) const
    {
        if (level == options_.depth || members.size() <= 1) return;
        std::mt19937_64 rng(mixSeed(key));
        std::vector<Elem> centres = seed(members, rng);
        const int k = static_cast<int>(centres.size() / m_.n);
        std::vector<int> cluster = lloyd(members, centres, k);

        std::vector<std::vector<int>> member_lists(k);
        for (size_t i = 0; i < members.size(); ++i) member_lists[cluster[i]].push_back(members[i]);
        std::vector<int> non_empty;
        for (int c = 0; c < k; ++c)
            if (!member_lists[c].empty()) non_empty.push_back(c);
        if (non_empty.size() <= 1) return;  // all members identical: nothing to split
        std::vector<int>().swap(members);   // the children own the members from here on

        node.children.resize(non_empty.size());
        auto build_child = [&](int i) {
            const int c = non_empty[i];
            node.children[i].centre.assign(centres.begin() + size_t(c) * m_.n, centres.begin() + size_t(c + 1) * m_.n);
            build(node.children[i], std::move(member_lists[c]), level + 1, key * 1000003ull + uint64_t(i) + 1);
        };
        // The root's subtrees are independent and about equally large: one task each. Deeper levels run
        // inside these tasks (OpenCV runs nested parallel regions serially).
        if (level == 0)
            cv::parallel_for_(cv::Range(0, int(non_empty.size())), [&](const cv::Range& r) {
                for (int i = r.start; i < r.end; ++i) build_child(i);
            });
        else
            for (int i = 0; i < int(non_empty.size()); ++i) build_child(i);
    }

   private:
    const Elem* row(int i) const { return data_.data() + size_t(i) * m_.n; }

    /** k-means++: the first centre uniformly, each next one with probability proportional to the squared
     *  distance to the nearest centre so far. Stops early when every member coincides with a centre. */
    std::vector<Elem> seed(const std::vector<int>& members, std::mt19937_64& rng) const
    {
        const size_t n = members.size();
        const int k = static_cast<int>(std::min<size_t>(options_.branching, n));
        const int first = members[std::uniform_int_distribution<size_t>(0, n - 1)(rng)];
        std::vector<Elem> centres(row(first), row(first) + m_.n);
        std::vector<double> weight(n);
        for (size_t i = 0; i < n; ++i) weight[i] = seedingWeight(m_, row(members[i]), row(first));
        for (int c = 1; c < k; ++c)
        {
            const double total = std::accumulate(weight.begin(), weight.end(), 0.0);
            if (!(total > 0)) break;
            const double target = std::uniform_real_distribution<double>(0, total)(rng);
            size_t pick = n;
            double cumulative = 0;
            for (size_t i = 0; i < n && pick == n; ++i)
                if (weight[i] > 0 && (cumulative += weight[i]) > target) pick = i;
            if (pick == n)  // rounding: take the last candidate
                for (size_t i = n; i-- > 0 && pick == n;)
                    if (weight[i] > 0) pick = i;
            const Elem* chosen = row(members[pick]);
            centres.insert(centres.end(), chosen, chosen + m_.n);
            const std::vector<Elem> chosen_copy(chosen, chosen + m_.n);
            for (size_t i = 0; i < n; ++i)
                weight[i] = std::min(weight[i], seedingWeight(m_, row(members[i]), chosen_copy.data()));
        }
        return centres;
    }

    void assign(const std::vector<int>& members, const std::vector<Elem>& centres, int k,
                std::vector<int>& cluster) const
    {
        auto body = [&](const cv::Range& r) {
            for (int i = r.start; i < r.end; ++i) cluster[i] = m_.nearest(row(members[i]), centres.data(), k);
        };
        const cv::Range all(0, int(members.size()));
        if (members.size() * size_t(k) >= kParallelWork)
            cv::parallel_for_(all, body);
        else
            body(all);
    }

    /** Lloyd iterations; returns the assignment to the final centres (so every member is nearest to the
     *  centre of its own cluster, which the greedy descent relies on). An emptied cluster keeps its centre. */
    std::vector<int> lloyd(const std::vector<int>& members, std::vector<Elem>& centres, int k) const
    {
        std::vector<int> cluster(members.size()), previous;
        assign(members, centres, k, cluster);
        for (int it = 0; it < options_.kmeans_iterations; ++it)
        {
            std::vector<std::vector<int>> lists(k);
            for (size_t i = 0; i < members.size(); ++i) lists[cluster[i]].push_back(members[i]);
            for (int c = 0; c < k; ++c)
                if (!lists[c].empty()) m_.centre(data_.data(), lists[c], centres.data() + size_t(c) * m_.n);
            previous.swap(cluster);
            cluster.resize(members.size());
            assign(members, centres, k, cluster);
            if (cluster == previous) break;
        }
        return cluster;
    }

    Metric m_;
    const std::vector<Elem>& data_;
    const VocabularyOptions& options_;
};

/** The build tree in breadth-first order, so that the children of a node are contiguous. */
template <class Elem>
struct FlatTree
{
    std::vector<int32_t> first_child, num_children, node_word;
    std::vector<Elem> centres;
    int num_words = 0;
};

template <class Elem>
FlatTree<Elem> flatten(const BuildNode<Elem>& root, int row_elements)
{
    FlatTree<Elem> flat;
    std::vector<const BuildNode<Elem>*> order{&root};
    for (size_t i = 0; i < order.size(); ++i)
    {
        const BuildNode<Elem>& node = *order[i];
        const bool leaf = node.children.empty();
        flat.first_child.push_back(leaf ? -1 : int32_t(order.size()));
        flat.num_children.push_back(int32_t(node.children.size()));
        flat.node_word.push_back(leaf ? flat.num_words++ : -1);
        if (i == 0)
            flat.centres.resize(row_elements, Elem(0));  // the root has no centre
        else
            flat.centres.insert(flat.centres.end(), node.centre.begin(), node.centre.end());
        for (const auto& child : node.children) order.push_back(&child);
    }
    return flat;
}

template <class Metric>
FlatTree<typename Metric::Elem> buildTree(Metric metric, const std::vector<typename Metric::Elem>& data,
                                          const VocabularyOptions& options)
{
    const int rows = static_cast<int>(data.size() / metric.n);
    std::vector<int> members(rows);
    std::iota(members.begin(), members.end(), 0);
    BuildNode<typename Metric::Elem> root;
    TreeBuilder<Metric>(metric, data, options).build(root, std::move(members), 0, uint64_t(options.seed));
    return flatten(root, metric.n);
}

std::string typeName(int type) { return cv::typeToString(type); }

int rowElements(int type, int cols) { return type == CV_8U ? (cols + 7) / 8 : cols; }

/** Copies descriptor row `r` into `out` (row_elements uint64, the tail zero-padded) for the Hamming loops. */
void packBinaryRow(const cv::Mat& m, int r, int row_elements, uint64_t* out)
{
    std::memset(out, 0, size_t(row_elements) * 8);
    std::memcpy(out, m.ptr<uint8_t>(r), size_t(m.cols));
}

/** Validates the training Mats: one common type (CV_8U or CV_32F, one channel) and width; returns them. */
std::pair<int, int> trainingFormat(const std::vector<cv::Mat>& mats)
{
    const std::string input = "Vocabulary::train descriptors";
    int type = -1, cols = 0, first = -1;
    for (size_t i = 0; i < mats.size(); ++i)
    {
        const cv::Mat& m = mats[i];
        if (m.empty()) continue;
        const std::string name = input + " (image " + std::to_string(i) + ")";
        core::require(m.type() == CV_8U || m.type() == CV_32F, name,
                      "descriptor type " + typeName(m.type()) + " is neither CV_8U (binary) nor CV_32F (float)");
        if (first < 0) type = m.type(), cols = m.cols, first = int(i);
        core::require(m.type() == type && m.cols == cols, name,
                      "mixed descriptors: " + std::to_string(m.cols) + " columns of " + typeName(m.type()) +
                          ", but image " + std::to_string(first) + " has " + std::to_string(cols) + " of " +
                          typeName(type));
        if (type == CV_32F) core::require(cv::checkRange(m), name, "NaN or infinite value in a float descriptor");
    }
    core::require(first >= 0, input, "no training descriptors (" + std::to_string(mats.size()) + " images, all empty)");
    return {type, cols};
}

/** The (image, row) of every descriptor used for clustering: all of them, or a seeded random subsample. */
std::vector<std::pair<int, int>> trainingRows(const std::vector<cv::Mat>& mats, const VocabularyOptions& options)
{
    std::vector<std::pair<int, int>> rows;
    for (size_t i = 0; i < mats.size(); ++i)
        for (int r = 0; r < mats[i].rows; ++r) rows.emplace_back(int(i), r);
    const size_t keep = size_t(options.max_training_descriptors);
    if (rows.size() <= keep) return rows;
    std::mt19937_64 rng(mixSeed(~uint64_t(options.seed)));
    for (size_t i = 0; i < keep; ++i)  // partial Fisher-Yates: the first `keep` entries are a uniform sample
        std::swap(rows[i], rows[i + std::uniform_int_distribution<size_t>(0, rows.size() - 1 - i)(rng)]);
    rows.resize(keep);
    std::sort(rows.begin(), rows.end());  // memory order: faster packing, and the order is not random-looking
    return rows;
}

}  // namespace

// ---------------------------------------------------------------------------------------------- options

void VocabularyOptions::declare(core::OptionTable& t)
{
    using core::Range;
    t.add("branching", branching, "", Range::between(2, 256), "k of the hierarchical k-means");
    t.add("depth", depth, "", Range::between(1, 16), "levels below the root (at most branching^depth words)");
    t.add("max_training_descriptors", max_training_descriptors, "", Range::atLeast(1),
          "random (seeded) subsample of the training descriptors");
    t.add("kmeans_iterations", kmeans_iterations, "", Range::between(1, 1000),
          "Lloyd iterations per node (fewer when assignments settle)");
    t.add("seed", seed, "", Range::atLeast(0), "the only source of randomness: same input + seed = same tree");
}

void VocabularyOptions::check(const std::string& input) const
{
    checkRanges(input, kSection);
    core::require(std::pow(double(branching), double(depth)) <= double(kMaxWords),
                  input + ": " + core::iniKeyName(kSection, "depth"),
                  "branching^depth = " + std::to_string(branching) + "^" + std::to_string(depth) + " exceeds " +
                      std::to_string(kMaxWords) + " words");
}

// ---------------------------------------------------------------------------------------------- training

Vocabulary Vocabulary::train(const std::vector<cv::Mat>& descriptors_per_image, const VocabularyOptions& options)
{
    options.check("Vocabulary::train options");
    const auto [type, cols] = trainingFormat(descriptors_per_image);
    const std::vector<std::pair<int, int>> rows = trainingRows(descriptors_per_image, options);

    Vocabulary voc;
    voc.descriptor_type_ = type;
    voc.descriptor_cols_ = cols;
    voc.row_elements_ = rowElements(type, cols);
    const int n = voc.row_elements_;
    auto adopt = [&voc](auto&& flat, auto& centres) {
        voc.first_child_ = std::move(flat.first_child);
        voc.num_children_ = std::move(flat.num_children);
        voc.node_word_ = std::move(flat.node_word);
        centres = std::move(flat.centres);
        voc.idf_.assign(flat.num_words, 0.f);
    };
    if (type == CV_8U)
    {
        std::vector<uint64_t> data(rows.size() * n);
        for (size_t i = 0; i < rows.size(); ++i)
            packBinaryRow(descriptors_per_image[rows[i].first], rows[i].second, n, data.data() + i * n);
        adopt(buildTree(HammingMetric{n}, data, options), voc.binary_centres_);
    }
    else
    {
        std::vector<float> data(rows.size() * n);
        for (size_t i = 0; i < rows.size(); ++i)
            std::memcpy(data.data() + i * n, descriptors_per_image[rows[i].first].ptr<float>(rows[i].second),
                        sizeof(float) * n);
        adopt(buildTree(L2Metric{n}, data, options), voc.float_centres_);
    }

    // idf over every descriptor of every image (the subsample only shaped the tree).
    const size_t num_images = descriptors_per_image.size();
    std::vector<std::vector<WordId>> image_words(num_images);
    cv::parallel_for_(cv::Range(0, int(num_images)), [&](const cv::Range& r) {
        for (int i = r.start; i < r.end; ++i)
        {
            std::vector<WordId> w = voc.words(descriptors_per_image[i]);
            std::sort(w.begin(), w.end());
            w.erase(std::unique(w.begin(), w.end()), w.end());
            image_words[i] = std::move(w);
        }
    });
    std::vector<int> images_with_word(voc.idf_.size(), 0);
    for (const auto& w : image_words)
        for (WordId id : w) ++images_with_word[id];
    for (size_t w = 0; w < voc.idf_.size(); ++w)  // every leaf holds a training row, so the count is >= 1
        voc.idf_[w] = static_cast<float>(std::log(double(num_images) / double(std::max(1, images_with_word[w]))));
    return voc;
}

// ---------------------------------------------------------------------------------------------- lookup

void Vocabulary::checkDescriptors(const cv::Mat& d, const std::string& input) const
{
    core::require(!empty(), input, "the vocabulary is empty (not trained or read)");
    core::require(d.type() == descriptor_type_ && d.cols == descriptor_cols_, input,
                  "descriptors of " + std::to_string(d.cols) + " columns of " + typeName(d.type()) +
                      ", but the vocabulary was trained on " + std::to_string(descriptor_cols_) + " columns of " +
                      typeName(descriptor_type_));
}

WordId Vocabulary::descend(const void* row) const
{
    int node = 0;
    if (binary())
    {
        const auto* x = static_cast<const uint64_t*>(row);
        while (first_child_[node] >= 0)
        {
            const int first = first_child_[node];
            node = first + nearestHamming(x, binary_centres_.data() + size_t(first) * row_elements_,
                                          num_children_[node], row_elements_);
        }
    }
    else
    {
        const L2Metric metric{row_elements_};
        const auto* x = static_cast<const float*>(row);
        while (first_child_[node] >= 0)
        {
            const int first = first_child_[node];
            node =
                first + metric.nearest(x, float_centres_.data() + size_t(first) * row_elements_, num_children_[node]);
        }
    }
    return static_cast<WordId>(node_word_[node]);
}

WordId Vocabulary::word(const cv::Mat& descriptors, int row) const
{
    checkDescriptors(descriptors, "Vocabulary::word descriptors");
    core::require(row >= 0 && row < descriptors.rows, "Vocabulary::word row",
                  std::to_string(row) + " is outside [0, " + std::to_string(descriptors.rows) + ")");
    if (!binary()) return descend(descriptors.ptr<float>(row));
    std::vector<uint64_t> packed(row_elements_);
    packBinaryRow(descriptors, row, row_elements_, packed.data());
    return descend(packed.data());
}

std::vector<WordId> Vocabulary::words(const cv::Mat& descriptors) const
{
    if (descriptors.empty()) return {};
    checkDescriptors(descriptors, "Vocabulary descriptors");
    std::vector<WordId> out(descriptors.rows);
    std::vector<uint64_t> packed(row_elements_);
    for (int r = 0; r < descriptors.rows; ++r)
    {
        if (!binary())
        {
            out[r] = descend(descriptors.ptr<float>(r));
            continue;
        }
        packBinaryRow(descriptors, r, row_elements_, packed.data());
        out[r] = descend(packed.data());
    }
    return out;
}

BowVector Vocabulary::transform(const cv::Mat& descriptors) const { return bowVector(words(descriptors)); }

BowVector Vocabulary::bowVector(std::vector<WordId> w) const
{
    for (WordId id : w)
        core::require(id < idf_.size(), "Vocabulary::bowVector", "word " + std::to_string(id) + " out of range");
    std::sort(w.begin(), w.end());
    BowVector v;
    double total = 0;
    for (size_t i = 0; i < w.size();)
    {
        size_t j = i;
        while (j < w.size() && w[j] == w[i]) ++j;
        // tf = count / rows; the 1/rows factor cancels in the L1 normalisation below.
        const float weight = float(j - i) * idf_[w[i]];
        if (weight > 0) v.emplace_back(w[i], weight), total += weight;
        i = j;
    }
    for (auto& [id, weight] : v) weight = static_cast<float>(weight / total);
    return v;
}

cv::Mat Vocabulary::centre(int node) const
{
    core::require(node >= 0 && node < numNodes(), "Vocabulary::centre node", std::to_string(node) + " out of range");
    cv::Mat out(1, descriptor_cols_, descriptor_type_);
    if (binary())
        std::memcpy(out.data, binary_centres_.data() + size_t(node) * row_elements_, size_t(descriptor_cols_));
    else
        std::memcpy(out.data, float_centres_.data() + size_t(node) * row_elements_, sizeof(float) * descriptor_cols_);
    return out;
}

// ---------------------------------------------------------------------------------------------- archive
//
// Format (version 1, little-endian): 16-byte tag "quasiloc-vocab"; uint32 version; int32 descriptor type,
// descriptor columns, row elements; uint32 node count; int32[nodes] first_child, num_children, node_word;
// centres (nodes x row elements, uint64 or float); uint32 word count; float[words] idf.

namespace
{
const std::string kArchiveInput = "vocabulary archive";

template <typename T>
void writeArray(mrpt::serialization::CArchive& out, const std::vector<T>& v)
{
    if (!v.empty()) out.WriteBufferFixEndianness(v.data(), v.size());
}

/** Allocates as the data arrives (detail::readElements): the counts in the file are not trusted. */
template <typename T>
std::vector<T> readArray(mrpt::serialization::CArchive& in, size_t count, const std::string& what)
{
    try
    {
        return detail::readElements<T>(in, count, what.c_str());
    }
    catch (const std::exception&)
    {
        throw core::InputError(kArchiveInput, "truncated in " + what);
    }
}

/** Children ranges must tile nodes 1..n-1 in breadth-first order (which also rules out cycles), and the
 *  leaves must number the words 0..num_words-1 once each. */
void checkTree(const std::vector<int32_t>& first_child, const std::vector<int32_t>& num_children,
               const std::vector<int32_t>& node_word, size_t num_words)
{
    const size_t n = first_child.size();
    size_t next_child = 1;
    std::vector<char> word_seen(num_words, 0);
    for (size_t i = 0; i < n; ++i)
    {
        if (first_child[i] < 0)
        {
            const int32_t w = node_word[i];
            core::require(num_children[i] == 0 && w >= 0 && size_t(w) < num_words && !word_seen[w], kArchiveInput,
                          "corrupt tree: bad leaf " + std::to_string(i));
            word_seen[w] = 1;
            continue;
        }
        core::require(node_word[i] == -1 && size_t(first_child[i]) == next_child && num_children[i] >= 1 &&
                          next_child + size_t(num_children[i]) <= n,
                      kArchiveInput, "corrupt tree: bad inner node " + std::to_string(i));
        next_child += size_t(num_children[i]);
    }
    core::require(next_child == n, kArchiveInput, "corrupt tree: unreachable nodes");
    core::require(std::all_of(word_seen.begin(), word_seen.end(), [](char c) { return c != 0; }), kArchiveInput,
                  "corrupt tree: words without a leaf");
}
}  // namespace

void Vocabulary::write(mrpt::serialization::CArchive& out) const
{
    core::require(!empty(), "Vocabulary::write", "the vocabulary is empty (not trained or read)");
    out.WriteBuffer(kMagic, sizeof(kMagic));
    out.WriteAs<uint32_t>(kVersion);
    out.WriteAs<int32_t>(descriptor_type_);
    out.WriteAs<int32_t>(descriptor_cols_);
    out.WriteAs<int32_t>(row_elements_);
    out.WriteAs<uint32_t>(static_cast<uint32_t>(numNodes()));
    writeArray(out, first_child_);
    writeArray(out, num_children_);
    writeArray(out, node_word_);
    if (binary())
        writeArray(out, binary_centres_);
    else
        writeArray(out, float_centres_);
    out.WriteAs<uint32_t>(static_cast<uint32_t>(idf_.size()));
    writeArray(out, idf_);
}

Vocabulary Vocabulary::read(mrpt::serialization::CArchive& in)
{
    try
    {
        char magic[sizeof(kMagic)] = {};
        core::require(
            in.ReadBuffer(magic, sizeof(magic)) == sizeof(magic) && std::memcmp(magic, kMagic, sizeof(magic)) == 0,
            kArchiveInput, "not a quasiloc vocabulary (bad header)");
        const uint32_t version = in.ReadAs<uint32_t>();
        core::require(version == kVersion, kArchiveInput,
                      "version " + std::to_string(version) + " is not supported (this build reads " +
                          std::to_string(kVersion) + ")");
        Vocabulary v;
        v.descriptor_type_ = in.ReadAs<int32_t>();
        v.descriptor_cols_ = in.ReadAs<int32_t>();
        v.row_elements_ = in.ReadAs<int32_t>();
        core::require((v.descriptor_type_ == CV_8U || v.descriptor_type_ == CV_32F) && v.descriptor_cols_ > 0 &&
                          v.descriptor_cols_ <= 65536 &&
                          v.row_elements_ == rowElements(v.descriptor_type_, v.descriptor_cols_),
                      kArchiveInput, "corrupt descriptor format");
        const uint32_t nodes = in.ReadAs<uint32_t>();
        const size_t elem_size = v.binary() ? sizeof(uint64_t) : sizeof(float);
        core::require(nodes >= 1 && uint64_t(nodes) * v.row_elements_ * elem_size <= (uint64_t(1) << 34), kArchiveInput,
                      "corrupt node count " + std::to_string(nodes));
        v.first_child_ = readArray<int32_t>(in, nodes, "the tree");
        v.num_children_ = readArray<int32_t>(in, nodes, "the tree");
        v.node_word_ = readArray<int32_t>(in, nodes, "the tree");
        const size_t centre_elements = size_t(nodes) * v.row_elements_;
        if (v.binary())
            v.binary_centres_ = readArray<uint64_t>(in, centre_elements, "the centres");
        else
            v.float_centres_ = readArray<float>(in, centre_elements, "the centres");
        const uint32_t num_words = in.ReadAs<uint32_t>();
        core::require(num_words >= 1 && num_words <= nodes, kArchiveInput,
                      "corrupt word count " + std::to_string(num_words));
        v.idf_ = readArray<float>(in, num_words, "the idf table");
        checkTree(v.first_child_, v.num_children_, v.node_word_, num_words);
        core::require(std::all_of(v.idf_.begin(), v.idf_.end(), [](float x) { return std::isfinite(x) && x >= 0; }),
                      kArchiveInput, "corrupt idf table");
        core::require(
            std::all_of(v.float_centres_.begin(), v.float_centres_.end(), [](float x) { return std::isfinite(x); }),
            kArchiveInput, "corrupt float centres");
        return v;
    }
    catch (const core::InputError&)
    {
        throw;
    }
    catch (const std::exception& e)  // MRPT's end-of-stream and read errors
    {
        throw core::InputError(kArchiveInput, std::string("truncated or unreadable: ") + e.what());
    }
}

}  // namespace quasiloc::reloc
