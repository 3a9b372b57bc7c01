// bench_vocabulary: the visual vocabulary's and inverted index's times against their budgets (a query's
// retrieval must leave the Fast budget to matching and PnP). Synthetic ORB-like (32 B) and float (64-d) scenes
// (src/synthetic_descriptors.h); prints one table.
//     build/bin/bench_vocabulary
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <quasiloc/reloc/inverted_index.h>
#include <quasiloc/reloc/vocabulary.h>
#include <random>

#include "../src/synthetic_descriptors.h"

using namespace quasiloc::reloc;
using namespace quasiloc::reloc::testing_support;

namespace
{
double msSince(std::chrono::steady_clock::time_point t0)
{
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

void row(const char* what, double ms, const char* budget, bool met)
{
    std::printf("| %s | %.3f | %s%s |\n", what, ms, budget, *budget ? (met ? " (met)" : " (MISSED)") : "");
}
}  // namespace

int main()
{
    const int reps = 20;
    std::printf("| stage | ms | budget |\n|---|---|---|\n");
    for (const bool binary : {true, false})
    {
        const DescriptorKind kind{binary, binary ? 32 : 64};
        const std::vector<cv::Mat> images = sceneImages(kind, 200, 1000, 50000, binary ? 23 : 29);
        auto t0 = std::chrono::steady_clock::now();
        const Vocabulary voc = Vocabulary::train(images, VocabularyOptions{});  // k = 10, depth 4, 200k rows
        row(binary ? "train 200000 x 32 B (k = 10, depth 4)" : "train 200000 x 64 float", msSince(t0), "", true);
        t0 = std::chrono::steady_clock::now();
        std::vector<BowVector> queries;
        for (int r = 0; r < reps; ++r) queries.push_back(voc.transform(images[size_t(r)]));
        const double transform_ms = msSince(t0) / reps;
        row(binary ? "transform 1000 ORB descriptors" : "transform 1000 float descriptors", transform_ms, "<= 2",
            transform_ms <= 2);
        if (!binary) continue;
        // 5000 database images: the 200 real vectors, then vectors of 1000 random words (typical list lengths).
        InvertedIndex index;
        std::mt19937 rng(3);
        for (int i = 0; i < 5000; ++i)
        {
            if (i < 200)
            {
                index.add(i, voc.transform(images[size_t(i)]));
                continue;
            }
            std::vector<WordId> words(1000);
            for (auto& w : words) w = WordId(rng() % voc.numWords());
            std::sort(words.begin(), words.end());
            BowVector v;
            for (WordId w : words)
                if (v.empty() || v.back().first != w) v.emplace_back(w, 1.f);
            index.add(i, v);
        }
        t0 = std::chrono::steady_clock::now();
        std::vector<RetrievalHit> hits;
        for (int r = 0; r < reps; ++r) hits = index.query(queries[size_t(r)], 50);
        const double query_ms = msSince(t0) / reps;
        row("query over 5000 images (top 50)", query_ms, "<= 5", query_ms <= 5);
        if (hits.empty() || hits[0].image != reps - 1)
        {
            std::fprintf(stderr, "bench_vocabulary: the last query did not retrieve its own image first\n");
            return 1;
        }
    }
    return 0;
}
