#pragma once
// tf-idf inverted index over bag-of-words vectors: for every word, the images containing it and its weight
// there, so that a query only touches the images it shares a word with.
#include <mrpt/serialization/CArchive.h>
#include <quasiloc/reloc/vocabulary.h>

#include <cstdint>
#include <unordered_map>
#include <vector>

namespace quasiloc::reloc
{
struct RetrievalHit
{
    int image = -1;
    float score = 0;  ///< in [0, 1]; 1 for identical vectors
};

class InvertedIndex
{
   public:
    /** Adds an image's vector (re-normalised to L1 = 1 here, so any positive weights work). Image ids need
     *  not be contiguous. InputError on a duplicate id, words not strictly increasing, or a weight that is
     *  negative or not finite. An empty vector is allowed (the image then never scores). */
    void add(int image_id, const BowVector& v);

    /** DBoW2's L1 score s = 1 - 0.5 * |a - b|_1 of L1-normalised a, b. For such vectors
     *  |a - b|_1 = 2 + sum over shared words of (|a_i - b_i| - a_i - b_i) = 2 - 2 sum min(a_i, b_i), so
     *  s = sum over shared words of min(a_i, b_i), accumulated through the query words' inverted lists.
     *  Best first (ties: smaller image id), at most top_n, only images sharing a word with the query.
     *  Same InputErrors on `v` as add(). */
    std::vector<RetrievalHit> query(const BowVector& v, int top_n) const;

    size_t size() const { return image_ids_.size(); }
    /** Total number of (word, image) entries; memory is about 8 bytes each. */
    size_t numEntries() const;

    /** Versioned binary form; read() throws InputError on a bad header, version or corrupt data. */
    void write(mrpt::serialization::CArchive& out) const;
    static InvertedIndex read(mrpt::serialization::CArchive& in);

   private:
    struct Entry
    {
        int32_t slot;  // index into image_ids_
        float weight;
    };
    std::vector<int> image_ids_;                            // by slot, in insertion order
    std::unordered_map<int, int32_t> slot_of_image_;        // image id -> slot
    std::unordered_map<WordId, std::vector<Entry>> lists_;  // word -> entries, slots increasing
};

}  // namespace quasiloc::reloc
