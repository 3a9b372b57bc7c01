#include <quasiloc/core/error.h>
#include <quasiloc/reloc/inverted_index.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

#include "archive_io.h"

namespace quasiloc::reloc
{
namespace
{
constexpr char kMagic[16] = "quasiloc-invidx";
constexpr uint32_t kVersion = 1;
const std::string kArchiveInput = "inverted index archive";

/** The vector scaled to L1 = 1 (empty if its weights sum to 0), after checking it is a valid BowVector. */
BowVector normalised(const BowVector& v, const std::string& input)
{
    double total = 0;
    for (size_t i = 0; i < v.size(); ++i)
    {
        core::require(i == 0 || v[i].first > v[i - 1].first, input,
                      "words not strictly increasing at entry " + std::to_string(i));
        core::require(std::isfinite(v[i].second) && v[i].second >= 0, input,
                      "weight of word " + std::to_string(v[i].first) + " is negative or not finite");
        total += v[i].second;
    }
    BowVector out;
    if (!(total > 0)) return out;
    out.reserve(v.size());
    for (const auto& [word, weight] : v)
        if (weight > 0) out.emplace_back(word, static_cast<float>(weight / total));
    return out;
}
}  // namespace

void InvertedIndex::add(int image_id, const BowVector& v)
{
    const std::string input = "InvertedIndex::add image " + std::to_string(image_id);
    core::require(slot_of_image_.count(image_id) == 0, input, "image id already in the index");
    const BowVector n = normalised(v, input);
    const auto slot = static_cast<int32_t>(image_ids_.size());
    image_ids_.push_back(image_id);
    slot_of_image_.emplace(image_id, slot);
    for (const auto& [word, weight] : n) lists_[word].push_back({slot, weight});
}

std::vector<RetrievalHit> InvertedIndex::query(const BowVector& v, int top_n) const
{
    const BowVector q = normalised(v, "InvertedIndex::query vector");
    if (top_n <= 0 || q.empty()) return {};

    // For L1-normalised vectors |q_i - d_i| - q_i - d_i = -2 min(q_i, d_i), so the score is the sum of
    // min(q_i, d_i) over shared words; weights are > 0, so a slot sharing a word has a positive sum.
    std::vector<float> score(image_ids_.size(), 0.f);
    for (const auto& [word, qw] : q)
    {
        const auto it = lists_.find(word);
        if (it == lists_.end()) continue;
        for (const Entry& e : it->second) score[e.slot] += std::min(qw, e.weight);
    }

    std::vector<RetrievalHit> hits;
    for (size_t slot = 0; slot < score.size(); ++slot)
        if (score[slot] > 0) hits.push_back({image_ids_[slot], std::min(score[slot], 1.f)});
    const auto better = [](const RetrievalHit& a, const RetrievalHit& b) {
        return a.score > b.score || (a.score == b.score && a.image < b.image);
    };
    const size_t keep = std::min(hits.size(), size_t(top_n));
    std::partial_sort(hits.begin(), hits.begin() + keep, hits.end(), better);
    hits.resize(keep);
    return hits;
}

size_t InvertedIndex::numEntries() const
{
    size_t n = 0;
    for (const auto& [word, list] : lists_) n += list.size();
    return n;
}

// Format (version 1, little-endian): 16-byte tag "quasiloc-invidx"; uint32 version; uint32 image count;
// int32[images] image ids by slot; uint32 list count; per list, in increasing word order: uint32 word,
// uint32 length, int32[length] slots, float[length] weights.

void InvertedIndex::write(mrpt::serialization::CArchive& out) const
{
    out.WriteBuffer(kMagic, sizeof(kMagic));
    out.WriteAs<uint32_t>(kVersion);
    out.WriteAs<uint32_t>(static_cast<uint32_t>(image_ids_.size()));
    if (!image_ids_.empty()) out.WriteBufferFixEndianness(image_ids_.data(), image_ids_.size());
    std::vector<WordId> words;
    words.reserve(lists_.size());
    for (const auto& [word, list] : lists_) words.push_back(word);
    std::sort(words.begin(), words.end());  // a deterministic file for the same index
    out.WriteAs<uint32_t>(static_cast<uint32_t>(words.size()));
    for (WordId word : words)
    {
        const std::vector<Entry>& list = lists_.at(word);
        out.WriteAs<uint32_t>(word);
        out.WriteAs<uint32_t>(static_cast<uint32_t>(list.size()));
        std::vector<int32_t> slots(list.size());
        std::vector<float> weights(list.size());
        for (size_t i = 0; i < list.size(); ++i) slots[i] = list[i].slot, weights[i] = list[i].weight;
        if (!list.empty())
        {
            out.WriteBufferFixEndianness(slots.data(), slots.size());
            out.WriteBufferFixEndianness(weights.data(), weights.size());
        }
    }
}

InvertedIndex InvertedIndex::read(mrpt::serialization::CArchive& in)
{
    constexpr uint32_t kMaxCount = 1u << 28;  // a corrupt count must not allocate gigabytes
    try
    {
        char magic[sizeof(kMagic)] = {};
        core::require(
            in.ReadBuffer(magic, sizeof(magic)) == sizeof(magic) && std::memcmp(magic, kMagic, sizeof(magic)) == 0,
            kArchiveInput, "not a quasiloc inverted index (bad header)");
        const uint32_t version = in.ReadAs<uint32_t>();
        core::require(version == kVersion, kArchiveInput,
                      "version " + std::to_string(version) + " is not supported (this build reads " +
                          std::to_string(kVersion) + ")");
        InvertedIndex index;
        const uint32_t images = in.ReadAs<uint32_t>();
        core::require(images <= kMaxCount, kArchiveInput, "corrupt image count " + std::to_string(images));
        index.image_ids_ = detail::readElements<int32_t>(in, images, "image ids");  // grows with the data
        for (uint32_t s = 0; s < images; ++s)
            core::require(index.slot_of_image_.emplace(index.image_ids_[s], int32_t(s)).second, kArchiveInput,
                          "duplicate image id " + std::to_string(index.image_ids_[s]));
        const uint32_t num_lists = in.ReadAs<uint32_t>();
        core::require(num_lists <= kMaxCount, kArchiveInput, "corrupt list count " + std::to_string(num_lists));
        for (uint32_t l = 0; l < num_lists; ++l)
        {
            const WordId word = in.ReadAs<uint32_t>();
            const uint32_t length = in.ReadAs<uint32_t>();
            core::require(length <= images && index.lists_.count(word) == 0, kArchiveInput,
                          "corrupt list of word " + std::to_string(word));
            if (length == 0) continue;
            const std::vector<int32_t> slots = detail::readElements<int32_t>(in, length, "inverted list");
            const std::vector<float> weights = detail::readElements<float>(in, length, "inverted list");
            std::vector<Entry>& list = index.lists_[word];
            list.resize(length);
            for (uint32_t i = 0; i < length; ++i)
            {
                list[i] = {slots[i], weights[i]};
                core::require(
                    slots[i] >= 0 && uint32_t(slots[i]) < images && std::isfinite(weights[i]) && weights[i] > 0,
                    kArchiveInput, "corrupt entry in the list of word " + std::to_string(word));
            }
        }
        return index;
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
