#pragma once
// Visual vocabulary: a hierarchical k-means tree over local descriptors (a "vocabulary tree", as in DBoW2)
// whose leaves are the visual words, with an idf weight per word learnt from the training images.
// Binary descriptors (CV_8U rows, e.g. ORB's 32 bytes) are clustered under the Hamming distance with per-bit
// majority centres; float descriptors (CV_32F rows, e.g. SIFT, XFeat) under L2 with mean centres.
#include <mrpt/serialization/CArchive.h>

#include <cstdint>
#include <opencv2/core.hpp>
#include <quasiloc/core/declared_options.h>
#include <string>
#include <utility>
#include <vector>

namespace quasiloc::reloc
{
/** Training options; INI section [Vocabulary] (VocabularyOptions::declare, vocabulary.cpp). */
struct VocabularyOptions : public core::DeclaredOptions
{
    int branching = 10;                     ///< k of the hierarchical k-means
    int depth = 4;                          ///< levels below the root (at most branching^depth words)
    int max_training_descriptors = 200000;  ///< random (seeded) subsample of the training descriptors
    int kmeans_iterations = 10;             ///< Lloyd iterations per node (fewer when assignments settle)
    int seed = 1;                           ///< the only source of randomness: same input + seed = same tree

    void declare(core::OptionTable& t) override;
    /** InputError "<input>: [Vocabulary] <key>" for a value out of its declared range, or (depth) when
     *  branching^depth exceeds the word limit. */
    void check(const std::string& input) const;
};

using WordId = uint32_t;
/** Sparse bag-of-words vector: (word, weight) sorted by word, weights tf-idf, L1-normalised. */
using BowVector = std::vector<std::pair<WordId, float>>;

class Vocabulary
{
   public:
    /** Hierarchical k-means (k-means++ seeding) over the rows of all Mats (one Mat per training image, all of
     *  the same type and width; empty Mats allowed). idf of each word = log(N_images / n_images_containing_word),
     *  counted over all rows, not only the subsample used for clustering. InputError on no descriptors, mixed
     *  types or widths, an unsupported type, NaN/inf in float descriptors or bad options. */
    static Vocabulary train(const std::vector<cv::Mat>& descriptors_per_image, const VocabularyOptions& options);

    /** Word of one descriptor row: greedy descent choosing the nearest child centre at every level (the first
     *  one on a tie). InputError on a descriptor of another type or width, or a row out of range. */
    WordId word(const cv::Mat& descriptors, int row) const;
    /** tf-idf vector of all rows; an empty Mat gives an empty vector. Words with idf 0 (present in every
     *  training image) carry no information and are left out; if nothing is left the vector is empty. */
    BowVector transform(const cv::Mat& descriptors) const;
    /** The word of every row (for matching by shared words). */
    std::vector<WordId> words(const cv::Mat& descriptors) const;
    /** The tf-idf vector of words already found (transform(d) == bowVector(words(d))): lets a caller that needs
     *  both the words and the vector descend the tree once. InputError for a word out of range. */
    BowVector bowVector(std::vector<WordId> words) const;

    size_t numWords() const { return idf_.size(); }
    bool binary() const { return descriptor_type_ == CV_8U; }
    int descriptorCols() const { return descriptor_cols_; }
    int descriptorType() const { return descriptor_type_; }
    bool empty() const { return idf_.empty(); }
    float idf(WordId w) const { return idf_.at(w); }

    /** Versioned binary form; read() throws InputError on a bad header, version or corrupt data. */
    void write(mrpt::serialization::CArchive& out) const;
    static Vocabulary read(mrpt::serialization::CArchive& in);

    /** @name The tree (diagnostics and tests). Node 0 is the root (no centre); the children of a node are
     *  contiguous, numbered after it. @{ */
    int numNodes() const { return static_cast<int>(first_child_.size()); }
    int firstChild(int node) const { return first_child_.at(node); }  ///< -1 for a leaf
    int numChildren(int node) const { return num_children_.at(node); }
    int nodeWord(int node) const { return node_word_.at(node); }  ///< -1 for an inner node
    /** 1 x cols Mat of the descriptor type (the stored centre, unpadded). */
    cv::Mat centre(int node) const;
    /** @} */

   private:
    void checkDescriptors(const cv::Mat& descriptors, const std::string& input) const;
    /** Word of one row; `row` is row_elements_ uint64 (binary, zero-padded) or floats. */
    WordId descend(const void* row) const;

    int descriptor_type_ = -1;  // CV_8U or CV_32F
    int descriptor_cols_ = 0;   // bytes (binary) or floats per descriptor
    int row_elements_ = 0;      // stored elements per centre: uint64 words (binary, zero-padded) or floats
    std::vector<int32_t> first_child_, num_children_, node_word_;
    std::vector<uint64_t> binary_centres_;  // numNodes() x row_elements_
    std::vector<float> float_centres_;      // numNodes() x row_elements_
    std::vector<float> idf_;                // per word
};

}  // namespace quasiloc::reloc
