#pragma once
// Place descriptors for the coarse retrieval stage of global localization by geometry (place_retrieval.h): a
// horizontal range profile. Around a camera position, in `sectors` equal sectors of azimuth (world frame, gravity
// aligned), and in horizontal bands at band_centres_m above the camera (each band_half_m high on either side), the
// horizontal distance to the first surface, up to max_range_m: 2-D scans of the map at a few heights, a polar grid as
// in Scan Context, but holding what the camera can see (the first surface) rather than what is behind it (max
// height), because the query is a stereo cloud, which sees only first surfaces.
//
//  - of the map (placeProfile): rays cast on the distance field from the place, in each band at the heights
//    band_offsets_m about its centre, each cell's value the nearest first hit over those heights (max_range_m: no
//    hit);
//  - of a stereo query (queryProfile): its points levelled by gravity, each cell's value the nearest horizontal
//    range among the points in its band and sector; NaN where the stereo saw no point (out of its field of view,
//    beyond its depth, or no texture): those cells are not compared.
//
// Layout: band-major, cell (band b, sector k) at b x sectors + k.
//
// A query is compared with a place at every cyclic shift of its sectors (the unknown heading): profileCost.
//
// Options: the place_ keys of [GeometricLocalization] (GeometricLocalizationOptions::declare).
#include <Eigen/Core>
#include <quasiloc/map/distance_field.h>
#include <string>
#include <vector>

namespace quasiloc::reloc
{
struct PlaceDescriptorOptions
{
    int sectors = 72;
    double max_range_m = 4.0;
    std::vector<double> band_centres_m{-0.8, 0.0, 0.8};
    std::vector<double> band_offsets_m{-0.3, 0.0, 0.3};
    double band_half_m = 0.4;
    double hit_m = 0.06;
    double cost_truncation_m = 0.5;

    /** InputError naming `input` and the key (in `section`) for a value that cannot be used. */
    void check(const std::string& input, const std::string& section) const;
    bool operator==(const PlaceDescriptorOptions& o) const
    {
        return sectors == o.sectors && max_range_m == o.max_range_m && band_centres_m == o.band_centres_m &&
               band_offsets_m == o.band_offsets_m && band_half_m == o.band_half_m && hit_m == o.hit_m;
    }
    size_t cells() const { return size_t(sectors) * band_centres_m.size(); }
};

/** The map's profile at p_world (cells() values; sector k covers azimuths [k, k + 1) x 360 / sectors deg from world
 * +x). */
std::vector<float> placeProfile(const map::DistanceField& field, const Eigen::Vector3f& p_world,
                                const PlaceDescriptorOptions& o);

/** A query's profile from its points in the camera frame; R_level turns the camera frame into a gravity-aligned
 *  frame (its yaw is arbitrary: the cost searches the shift). Sectors with no point are NaN. */
std::vector<float> queryProfile(const std::vector<Eigen::Vector3f>& points_cam, const Eigen::Matrix3f& R_level,
                                const PlaceDescriptorOptions& o);

/** Cells of a query profile that hold a value (compared cells). */
std::vector<int> coveredSectors(const std::vector<float>& query);

/** Mean truncated squared range difference over the covered cells, query cell (b, j) against place cell
 *  (b, (j + shift) mod sectors): the query's frame turned by shift sectors about the vertical. */
float profileCost(const std::vector<float>& query, const std::vector<int>& covered, const float* place, int shift,
                  int sectors, float truncation_m);

}  // namespace quasiloc::reloc
