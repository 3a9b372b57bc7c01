#include <gtest/gtest.h>

#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/io/CMemoryStream.h>
#include <mrpt/serialization/CArchive.h>
#include <quasiloc/core/error.h>
#include <quasiloc/core/program_options.h>
#include <quasiloc/reloc/inverted_index.h>
#include <quasiloc/reloc/vocabulary.h>

#include "synthetic_descriptors.h"

#include <chrono>
#include <cstdio>
#include <functional>
#include <map>
#include <opencv2/core.hpp>
#include <random>

using namespace quasiloc::reloc;
using quasiloc::core::InputError;
using namespace quasiloc::reloc::testing_support;

namespace
{
VocabularyOptions smallOptions()
{
    VocabularyOptions o;
    o.branching = 8;
    o.depth = 3;
    return o;
}

/** The word a plain descent with cv::norm reaches (nearest child at every level, first on a tie). */
WordId referenceWord(const Vocabulary& voc, const cv::Mat& row)
{
    const int norm = voc.binary() ? cv::NORM_HAMMING : cv::NORM_L2SQR;
    int node = 0;
    while (voc.firstChild(node) >= 0)
    {
        int best = -1;
        double best_d = 0;
        for (int c = voc.firstChild(node); c < voc.firstChild(node) + voc.numChildren(node); ++c)
        {
            const double d = cv::norm(row, voc.centre(c), norm);
            if (best < 0 || d < best_d) best = c, best_d = d;
        }
        node = best;
    }
    return WordId(voc.nodeWord(node));
}

void expectDescentIsNearestChild(const DescriptorKind& kind)
{
    const std::vector<cv::Mat> images = sceneImages(kind, 5, 300, 400, 7);
    const Vocabulary voc = Vocabulary::train(images, smallOptions());
    ASSERT_GT(voc.numWords(), 8u);
    EXPECT_LE(voc.numWords(), 512u);
    std::vector<int> hits(voc.numWords(), 0);
    int mismatches = 0;
    for (const cv::Mat& m : images)
        for (int r = 0; r < m.rows; ++r)
        {
            const WordId w = voc.word(m, r);
            ASSERT_LT(w, voc.numWords());
            mismatches += (w != referenceWord(voc, m.row(r)));
            ++hits[w];
        }
    // Float: cv::norm and the SIMD kernel may round a near-tie differently; a handful at most.
    EXPECT_LE(mismatches, kind.binary ? 0 : 3);
    // Every leaf was made from training rows, so every word is some training row's word.
    for (size_t w = 0; w < hits.size(); ++w) EXPECT_GT(hits[w], 0) << "word " << w;
}

void expectDeterministic(const DescriptorKind& kind)
{
    const std::vector<cv::Mat> images = sceneImages(kind, 4, 200, 300, 3);
    const Vocabulary a = Vocabulary::train(images, smallOptions());
    const Vocabulary b = Vocabulary::train(images, smallOptions());
    ASSERT_EQ(a.numNodes(), b.numNodes());
    for (int n = 1; n < a.numNodes(); ++n) ASSERT_EQ(cv::norm(a.centre(n), b.centre(n), cv::NORM_INF), 0) << n;
    EXPECT_EQ(a.words(images[2]), b.words(images[2]));
    // The same descriptors in a non-continuous matrix (a column window of a wider one) give the same words.
    cv::Mat wide(images[2].rows, images[2].cols + 5, images[2].type(), cv::Scalar(0));
    cv::Mat window = wide.colRange(3, 3 + images[2].cols);
    images[2].copyTo(window);
    ASSERT_FALSE(window.isContinuous());
    EXPECT_EQ(a.words(window), a.words(images[2]));
    const std::vector<WordId> per_row = a.words(images[2]);
    for (int r = 0; r < images[2].rows; r += 17) EXPECT_EQ(a.word(window, r), per_row[r]);
}

/** Index of 20 images; each ranks itself first with score ~1, and so does a copy with 20% of its rows
 *  replaced by random descriptors. */
void expectRetrieval(const DescriptorKind& kind)
{
    const std::vector<cv::Mat> images = sceneImages(kind, 20, 400, 2000, 11);
    const Vocabulary voc = Vocabulary::train(images, VocabularyOptions{});
    InvertedIndex index;
    for (int i = 0; i < 20; ++i) index.add(100 + 3 * i, voc.transform(images[i]));  // ids not contiguous
    ASSERT_EQ(index.size(), 20u);
    std::mt19937 rng(5);
    for (int i = 0; i < 20; ++i)
    {
        const std::vector<RetrievalHit> hits = index.query(voc.transform(images[i]), 5);
        ASSERT_EQ(hits.size(), 5u);
        EXPECT_EQ(hits[0].image, 100 + 3 * i);
        EXPECT_NEAR(hits[0].score, 1.f, 1e-4);
        EXPECT_LT(hits[1].score, 0.5f);

        cv::Mat perturbed = images[i].clone();
        for (int r = 0; r < perturbed.rows; r += 5) randomDescriptors(kind, 1, rng).copyTo(perturbed.row(r));
        const std::vector<RetrievalHit> p = index.query(voc.transform(perturbed), 3);
        ASSERT_FALSE(p.empty());
        EXPECT_EQ(p[0].image, 100 + 3 * i);
        EXPECT_GT(p[0].score, 2 * p[1].score) << "image " << i;
    }
}

template <class T>
T roundTrip(const T& object)
{
    mrpt::io::CMemoryStream buffer;
    auto archive = mrpt::serialization::archiveFrom(buffer);
    object.write(archive);
    buffer.Seek(0);
    return T::read(archive);
}

void expectRoundTrip(const DescriptorKind& kind)
{
    const std::vector<cv::Mat> images = sceneImages(kind, 10, 300, 1000, 13);
    const Vocabulary voc = Vocabulary::train(images, smallOptions());
    const Vocabulary copy = roundTrip(voc);
    EXPECT_EQ(copy.numWords(), voc.numWords());
    EXPECT_EQ(copy.descriptorType(), voc.descriptorType());
    EXPECT_EQ(copy.descriptorCols(), voc.descriptorCols());
    InvertedIndex index;
    for (int i = 0; i < 10; ++i)
    {
        EXPECT_EQ(copy.words(images[i]), voc.words(images[i]));
        EXPECT_EQ(copy.transform(images[i]), voc.transform(images[i]));
        index.add(i, voc.transform(images[i]));
    }
    const InvertedIndex index_copy = roundTrip(index);
    ASSERT_EQ(index_copy.size(), index.size());
    EXPECT_EQ(index_copy.numEntries(), index.numEntries());
    for (int i = 0; i < 10; ++i)
    {
        const auto a = index.query(voc.transform(images[i]), 10), b = index_copy.query(copy.transform(images[i]), 10);
        ASSERT_EQ(a.size(), b.size());
        for (size_t h = 0; h < a.size(); ++h)
        {
            EXPECT_EQ(a[h].image, b[h].image);
            EXPECT_EQ(a[h].score, b[h].score);
        }
    }
}

void expectInputError(const std::function<void()>& f, const std::string& fragment)
{
    try
    {
        f();
        ADD_FAILURE() << "no InputError (expected one mentioning '" << fragment << "')";
    }
    catch (const InputError& e)
    {
        EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
}

}  // namespace

TEST(Vocabulary, BinaryDescentPicksTheNearestChildAtEveryLevel) { expectDescentIsNearestChild({true, 32}); }
TEST(Vocabulary, FloatDescentPicksTheNearestChildAtEveryLevel) { expectDescentIsNearestChild({false, 64}); }
TEST(Vocabulary, OddWidthBinaryDescriptors) { expectDescentIsNearestChild({true, 61}); }  // AKAZE: 61 bytes

TEST(Vocabulary, BinaryTrainingIsDeterministic) { expectDeterministic({true, 32}); }
TEST(Vocabulary, FloatTrainingIsDeterministic) { expectDeterministic({false, 64}); }

TEST(InvertedIndex, BinaryRetrievalRanksTheImageAndAPerturbedCopyFirst) { expectRetrieval({true, 32}); }
TEST(InvertedIndex, FloatRetrievalRanksTheImageAndAPerturbedCopyFirst) { expectRetrieval({false, 64}); }

TEST(Vocabulary, BinaryWriteReadRoundTrip) { expectRoundTrip({true, 32}); }
TEST(Vocabulary, FloatWriteReadRoundTrip) { expectRoundTrip({false, 64}); }

TEST(Vocabulary, TransformIsL1NormalisedTfIdf)
{
    const std::vector<cv::Mat> images = sceneImages({true, 32}, 6, 200, 300, 17);
    const Vocabulary voc = Vocabulary::train(images, smallOptions());
    const BowVector v = voc.transform(images[0]);
    ASSERT_FALSE(v.empty());
    std::map<WordId, int> counts;
    for (WordId w : voc.words(images[0])) ++counts[w];
    double sum = 0, expected_total = 0;
    for (const auto& [w, n] : counts) expected_total += n * voc.idf(w);
    for (size_t i = 0; i < v.size(); ++i)
    {
        if (i > 0)
        {
            EXPECT_LT(v[i - 1].first, v[i].first);
        }
        EXPECT_GT(v[i].second, 0.f);
        EXPECT_NEAR(v[i].second, counts.at(v[i].first) * voc.idf(v[i].first) / expected_total, 1e-6);
        sum += v[i].second;
    }
    EXPECT_NEAR(sum, 1.0, 1e-5);
    EXPECT_TRUE(voc.transform(cv::Mat()).empty());
    EXPECT_TRUE(voc.words(cv::Mat()).empty());
}

TEST(Vocabulary, BadInputThrowsInputErrorNamingTheProblem)
{
    expectInputError([] { Vocabulary::train({}, smallOptions()); }, "no training descriptors");
    expectInputError([] { Vocabulary::train({cv::Mat(), cv::Mat()}, smallOptions()); }, "no training descriptors");
    std::mt19937 rng(1);
    const cv::Mat orb = randomDescriptors({true, 32}, 50, rng), sift = randomDescriptors({false, 128}, 50, rng);
    expectInputError([&] { Vocabulary::train({orb, sift}, smallOptions()); }, "mixed descriptors");
    expectInputError(
        [&] {
            Vocabulary::train({orb, orb.colRange(0, 16).clone()}, smallOptions());
        },
        "mixed descriptors");
    cv::Mat nan_row = sift.clone();
    nan_row.at<float>(3, 7) = std::numeric_limits<float>::quiet_NaN();
    expectInputError([&] { Vocabulary::train({nan_row}, smallOptions()); }, "NaN");
    expectInputError([&] { Vocabulary::train({cv::Mat(5, 8, CV_16S, cv::Scalar(0))}, smallOptions()); },
                     "neither CV_8U");
    VocabularyOptions bad = smallOptions();
    bad.branching = 1;
    expectInputError([&] { Vocabulary::train({orb}, bad); }, "[Vocabulary] branching");

    const Vocabulary voc = Vocabulary::train({orb, orb}, smallOptions());
    const cv::Mat brisk = randomDescriptors({true, 64}, 10, rng);
    expectInputError([&] { voc.transform(brisk); }, "64 columns");
    expectInputError([&] { voc.transform(sift); }, "CV_32F");
    expectInputError([&] { voc.word(orb, 50); }, "row");
    expectInputError([] { Vocabulary().transform(cv::Mat(1, 32, CV_8U)); }, "empty");

    InvertedIndex index;
    index.add(1, {{1, 0.5f}, {4, 0.5f}});
    expectInputError([&] { index.add(1, {{2, 1.f}}); }, "already in the index");
    expectInputError([&] { index.add(2, {{4, 0.5f}, {1, 0.5f}}); }, "strictly increasing");
    expectInputError([&] { index.query({{3, -1.f}}, 5); }, "negative");
}

TEST(Vocabulary, CorruptArchivesThrowInputError)
{
    const std::vector<cv::Mat> images = sceneImages({true, 32}, 3, 100, 200, 19);
    const Vocabulary voc = Vocabulary::train(images, smallOptions());
    mrpt::io::CMemoryStream full;
    auto out = mrpt::serialization::archiveFrom(full);
    voc.write(out);
    const auto bytes = static_cast<const uint8_t*>(full.getRawBufferData());
    const size_t size = full.getTotalBytesCount();

    mrpt::io::CMemoryStream truncated;
    truncated.Write(bytes, size / 2);
    truncated.Seek(0);
    auto in_truncated = mrpt::serialization::archiveFrom(truncated);
    expectInputError([&] { Vocabulary::read(in_truncated); }, "vocabulary archive");

    mrpt::io::CMemoryStream garbage;
    const std::string text = "this is not a vocabulary, not at all";
    garbage.Write(text.data(), text.size());
    garbage.Seek(0);
    auto in_garbage = mrpt::serialization::archiveFrom(garbage);
    expectInputError([&] { Vocabulary::read(in_garbage); }, "bad header");

    std::vector<uint8_t> future(bytes, bytes + size);
    future[16] = 99;  // the version, right after the 16-byte tag
    mrpt::io::CMemoryStream versioned;
    versioned.Write(future.data(), future.size());
    versioned.Seek(0);
    auto in_versioned = mrpt::serialization::archiveFrom(versioned);
    expectInputError([&] { Vocabulary::read(in_versioned); }, "version 99");
}

TEST(VocabularyOptions, IniRoundTripAndCheck)
{
    mrpt::config::CConfigFileMemory ini;
    ini.write("Vocabulary", "branching", "6");
    ini.write("Vocabulary", "depth", "5");
    VocabularyOptions o;
    o.loadFromConfigFile(ini, "Vocabulary");
    EXPECT_EQ(o.branching, 6);
    EXPECT_EQ(o.depth, 5);
    EXPECT_EQ(o.seed, 1);
    mrpt::config::CConfigFileMemory saved;
    o.saveToConfigFile(saved, "Vocabulary");
    // Re-parsed from text, as a program reads it (MRPT reads padded keys back only from text).
    const mrpt::config::CConfigFileMemory text(saved.getContent());
    VocabularyOptions back;
    quasiloc::core::loadOptionsChecked(back, text, "Vocabulary", "test.ini");
    EXPECT_NO_THROW(back.check("test.ini"));
    EXPECT_EQ(back.branching, 6);
    EXPECT_EQ(back.max_training_descriptors, o.max_training_descriptors);
    ini.write("Vocabulary", "depth", "four");
    expectInputError([&] { o.loadFromConfigFile(ini, "Vocabulary"); }, "depth");
    o.depth = 40;
    expectInputError([&] { o.check("my.ini"); }, "my.ini: [Vocabulary] depth");
}
