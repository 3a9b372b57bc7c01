#include <gtest/gtest.h>

#include <quasiloc/map/lzf.h>
#include <random>
#include <string>

using namespace quasiloc::map;

namespace
{
std::vector<uint8_t> roundTrip(const std::vector<uint8_t>& data)
{
    const auto packed = lzfCompress(data.data(), data.size());
    std::vector<uint8_t> out(data.size());
    const auto n = lzfDecompress(packed.data(), packed.size(), out.data(), out.size());
    EXPECT_TRUE(n.has_value());
    out.resize(n.value_or(0));
    return out;
}
}  // namespace

TEST(Lzf, RoundTripOfVariedData)
{
    std::mt19937 rng(42);
    std::vector<std::vector<uint8_t>> inputs = {{}, {7}, {1, 2}, {1, 2, 3}, std::vector<uint8_t>(100000, 0xab)};
    std::vector<uint8_t> noise(70000);
    for (auto& b : noise) b = static_cast<uint8_t>(rng());
    inputs.push_back(noise);
    // Float point cloud channels (what PCD binary_compressed holds), repeated phrases, mixed content.
    std::vector<uint8_t> floats;
    std::normal_distribution<float> N(0.f, 10.f);
    for (int i = 0; i < 20000; ++i)
    {
        const float v = std::round(N(rng) * 100.f) / 100.f;
        const auto* p = reinterpret_cast<const uint8_t*>(&v);
        floats.insert(floats.end(), p, p + 4);
    }
    inputs.push_back(floats);
    std::string text;
    for (int i = 0; i < 3000; ++i) text += "vertex " + std::to_string(i % 37) + " lorem ipsum; ";
    inputs.emplace_back(text.begin(), text.end());
    for (size_t k = 0; k < inputs.size(); ++k) EXPECT_EQ(roundTrip(inputs[k]), inputs[k]) << "input " << k;
}

TEST(Lzf, CompressesRedundantData)
{
    const std::vector<uint8_t> zeros(1 << 20, 0);
    const auto packed = lzfCompress(zeros.data(), zeros.size());
    EXPECT_LT(packed.size(), zeros.size() / 50) << packed.size();
    std::string text;
    for (int i = 0; i < 5000; ++i) text += "the quick brown fox " + std::to_string(i % 10) + "\n";
    const auto p2 = lzfCompress(reinterpret_cast<const uint8_t*>(text.data()), text.size());
    EXPECT_LT(p2.size(), text.size() / 5) << p2.size();
}

TEST(Lzf, DecodesAHandWrittenStream)
{
    // literal "abc", back reference len 3 offset 3 -> "abc", long back reference (len 7 + 3 + 2 = 12,
    // offset 1: a run of the last byte), literal "Z".
    const std::vector<uint8_t> stream = {2, 'a', 'b', 'c', (1 << 5) | 0, 2, (7 << 5) | 0, 3, 0, 0, 'Z'};
    std::vector<uint8_t> out(64);
    const auto n = lzfDecompress(stream.data(), stream.size(), out.data(), out.size());
    ASSERT_TRUE(n.has_value());
    EXPECT_EQ(std::string(out.begin(), out.begin() + *n), "abcabc" + std::string(12, 'c') + "Z");
}

TEST(Lzf, RejectsCorruptStreams)
{
    std::vector<uint8_t> out(64);
    const std::vector<uint8_t> ref_before_start = {(1 << 5) | 0, 0};
    EXPECT_FALSE(lzfDecompress(ref_before_start.data(), ref_before_start.size(), out.data(), out.size()));
    const std::vector<uint8_t> short_literal = {5, 'a', 'b'};
    EXPECT_FALSE(lzfDecompress(short_literal.data(), short_literal.size(), out.data(), out.size()));
    const std::vector<uint8_t> missing_offset = {0, 'a', (1 << 5)};
    EXPECT_FALSE(lzfDecompress(missing_offset.data(), missing_offset.size(), out.data(), out.size()));
    const std::vector<uint8_t> far_ref = {1, 'a', 'b', (2 << 5) | 3, 0};  // offset 769 > 2 bytes written
    EXPECT_FALSE(lzfDecompress(far_ref.data(), far_ref.size(), out.data(), out.size()));
    const std::vector<uint8_t> data(100, 'q');
    const auto packed = lzfCompress(data.data(), data.size());
    std::vector<uint8_t> small(99);
    EXPECT_FALSE(lzfDecompress(packed.data(), packed.size(), small.data(), small.size())) << "output too small";
}
