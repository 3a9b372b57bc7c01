// Retrieval of the places whose range profiles match a query's (place_retrieval.h).
#include <opencv2/core/utility.hpp>
#include <quasiloc/reloc/place_retrieval.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace quasiloc::reloc
{
std::vector<RetrievedPlace> retrievePlaces(const PlaceIndex& index, const std::vector<float>& query,
                                           const RetrievalRequest& request, float cost_truncation_m)
{
    const int sectors = index.descriptor.sectors;
    const std::vector<int> covered = coveredSectors(query);
    std::vector<RetrievedPlace> best(index.size());
    cv::parallel_for_(cv::Range(0, int(index.size())), [&](const cv::Range& r) {
        for (int i = r.start; i < r.end; ++i)
        {
            RetrievedPlace& b = best[size_t(i)];
            b.place = size_t(i);
            b.cost = std::numeric_limits<float>::infinity();
            if (!request.admitted.empty() && !request.admitted[size_t(i)]) continue;
            for (int s = 0; s < sectors; ++s)
            {
                if (!request.shift_admitted.empty() && !request.shift_admitted[size_t(s)]) continue;
                const float c = profileCost(query, covered, index.profile(size_t(i)), s, sectors, cost_truncation_m);
                if (c < b.cost)
                {
                    b.cost = c;
                    b.shift = s;
                }
            }
        }
    });
    std::vector<size_t> order(best.size());
    std::iota(order.begin(), order.end(), size_t(0));
    std::sort(order.begin(), order.end(), [&](size_t a, size_t b) {
        return best[a].cost < best[b].cost || (best[a].cost == best[b].cost && a < b);
    });
    std::vector<RetrievedPlace> taken;
    const double suppress_shift = request.suppress_deg / 360.0 * sectors;
    for (size_t i : order)
    {
        if (taken.size() >= request.top_k || !std::isfinite(best[i].cost)) break;
        const Eigen::Vector3f& p = index.positions[i];
        const bool suppressed = std::any_of(taken.begin(), taken.end(), [&](const RetrievedPlace& t) {
            const Eigen::Vector3f& q = index.positions[t.place];
            const int ds = std::abs(best[i].shift - t.shift);
            return std::hypot(p.x() - q.x(), p.y() - q.y()) < request.suppress_m &&
                   std::min(ds, sectors - ds) <= suppress_shift;
        });
        if (!suppressed) taken.push_back(best[i]);
    }
    return taken;
}

}  // namespace quasiloc::reloc
