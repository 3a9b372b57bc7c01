#pragma once
// The coarse stage of global localization by geometry on a large map: the places (place_index.h) whose range
// profiles best match the query's (place_descriptor.h), each with the heading at which it matches. The geometric
// search (geometric_localizer.h) then scores only the candidate positions near these places, at headings near
// theirs.
//
// Every place is compared at every admitted cyclic shift; its cost is the best shift's. The places are taken in
// order of cost, skipping one within suppress_m (horizontally) of one already taken at a heading within
// suppress_deg: neighbouring places of one spot match alike, and K of them would crowd out the other rooms.
#include <Eigen/Core>
#include <quasiloc/reloc/place_index.h>
#include <vector>

namespace quasiloc::reloc
{
struct RetrievedPlace
{
    size_t place = 0;  ///< row in the PlaceIndex
    int shift = 0;     ///< sectors: the query's levelled frame turned by shift x 360 / sectors deg about world +z
    float cost = 0;    ///< profileCost at that shift
    double yawRad(int sectors) const { return 2 * M_PI * shift / sectors; }
};

struct RetrievalRequest
{
    size_t top_k = 50;
    double suppress_m = 1.0, suppress_deg = 20;
    /** Only places with admitted[row] (empty: all) and shifts with shift_admitted[shift] (empty: all). */
    std::vector<bool> admitted, shift_admitted;
};

/** The best top_k places for the query profile (place_descriptor.h queryProfile), best first; on every core. */
std::vector<RetrievedPlace> retrievePlaces(const PlaceIndex& index, const std::vector<float>& query,
                                           const RetrievalRequest& request, float cost_truncation_m);

}  // namespace quasiloc::reloc
