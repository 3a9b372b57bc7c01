#include <quasiloc/core/error.h>
#include <quasiloc/core/ini_read.h>
#include <quasiloc/reloc/geometric_localizer.h>

namespace quasiloc::reloc
{
namespace
{
void declareStereo(core::OptionTable& t, StereoCloudOptions& s)
{
    using core::Range;
    t.add("num_disparities", s.num_disparities, "px", Range::atLeast(16),
          "SGBM disparity range (a multiple of 16 x stereo_downscale)");
    t.add("block_size", s.block_size, "px", Range::atLeast(1), "SGBM block size (odd)");
    t.add("uniqueness_ratio", s.uniqueness_ratio, "%", Range::between(0, 100),
          "SGBM: the best cost must beat the second best by this percentage");
    t.add("min_depth_m", s.min_depth_m, "m", Range::above(0), "nearest stereo point kept");
    t.add("max_depth_m", s.max_depth_m, "m", Range::above(0), "farthest stereo point kept");
    t.add("query_voxel_m", s.voxel_m, "m", Range::atLeast(0), "one stereo point per voxel");
    t.add("max_points", s.max_points, "", Range::atLeast(10), "query points at most");
    t.add("disparity_sigma_px", s.disparity_sigma_px, "px", Range::atLeast(0),
          "depth noise z^2 / (f b) x this: each point's weight; an inlier may lie 2 depth sigmas farther");
    t.add("stereo_downscale", s.downscale, "", Range::between(1, 2), "1: full resolution; 2: SGBM on the halved pair");
}
}  // namespace

void GeometricLocalizationOptions::declare(core::OptionTable& t)
{
    using core::Range;
    t.add("field_voxel_m", field_voxel_m, "m", Range::above(0), "distance field (map::DistanceField) voxel");
    t.add("field_max_distance_m", field_max_distance_m, "m", Range::above(0), "distance field truncation");
    t.addEnum("field_layout", field_layout,
              {{"auto", map::DistanceFieldLayout::Auto},
               {"dense", map::DistanceFieldLayout::Dense},
               {"sparse", map::DistanceFieldLayout::Sparse},
               {"streamed", map::DistanceFieldLayout::Streamed}},
              "distance field storage: auto = a dense grid up to 50 M voxels (a room), sparse bricks beyond (a block); "
              "streamed = tiles around the camera only (a campus; docs/large_maps.md)");
    t.add("field_memory_budget_mb", field_memory_budget_mb, "MB", Range::above(0),
          "streamed field: tiles kept in memory at most (the least recently used evicted)");
    t.add("field_focus_radius_m", field_focus_radius_m, "m", Range::atLeast(0),
          "streamed field: the tracker readies the tiles within this distance of the camera every frame");
    t.add("field_tile_cache", field_tile_cache,
          "streamed field: folder of tiles on disk (map-build field_tile_cache writes it), read instead of built; "
          "tiles built are added; empty: none");
    declareStereo(t, stereo);
    t.add("grid_spacing_m", grid_spacing_m, "m", Range::above(0), "candidate position grid (view_sampling.h)");
    t.add("heights_m", heights_m, "m", Range::any(), "candidate heights above the floor");
    t.add("clearance_m", clearance_m, "m", Range::atLeast(0), "no map point closer to a candidate position");
    t.add("require_enclosed", require_enclosed, "indoors: positions enclosed by the map; false outdoors");
    t.add("ceiling_min_share", ceiling_min_share, "", Range::between(0, 1),
          "require_enclosed: a candidate needs a ceiling above it when at least this share of the wall-enclosed "
          "positions have one (a map whose mapping LiDAR saw the ceiling in part is enclosed by its walls alone)");
    t.add("region", region, "m", Range::any(), "optional [xmin ymin xmax ymax]: search only there");
    t.add("num_yaws", num_yaws, "", Range::between(1, 720), "headings per candidate position");
    t.add("score_points", score_points, "", Range::atLeast(10), "query points scored per coarse candidate");
    t.add("coarse_truncation_m", coarse_truncation_m, "m", Range::above(0), "coarse score truncation");
    t.add("refine_candidates", refine_candidates, "", Range::atLeast(1), "distinct candidates refined");
    t.add("refine_truncations_m", refine_truncations_m, "m", Range::above(0),
          "refinement truncations, shrinking (Gauss-Newton on the distance field)");
    t.add("refine_iterations", refine_iterations, "", Range::atLeast(1), "Gauss-Newton iterations per truncation");
    t.add("polish_truncations_m", polish_truncations_m, "m", Range::above(0),
          "point-to-point ICP of the best pose (empty: none)");
    t.add("inlier_m", inlier_m, "m", Range::above(0), "a query point this close to the map is an inlier");
    t.add("check_depth_along_normal", check_depth_along_normal,
          "the tracker's loss check: a point's depth tolerance (2 depth sigmas) counts only along the map's normal "
          "(times |ray . normal|), since a depth error moves a point along its ray: far points on surfaces seen at a "
          "grazing angle (the road, a street's facades) keep a tight tolerance across them (off by default: "
          "measured on the simulated campus car only, docs/benchmarks.md)");
    t.add("min_inlier_ratio", min_inlier_ratio, "", Range{0, 1, true, false}, "answer only with this share of inliers");
    t.add("ambiguity_ratio", ambiguity_ratio, "", Range{0, 1, true, false},
          "not localized when another place reaches this share of the answer's inliers");
    t.add("retrieval_min_positions", retrieval_min_positions, "", Range::atLeast(0),
          "place retrieval first when a search holds more candidate positions than this (a map of many rooms)");
    t.add("places_file", places_file,
          "place descriptors precomputed by quasiloc-build-places (empty: built when the map loads, on a large map)");
    t.add("place_spacing_m", place_spacing_m, "m", Range::above(0), "places: one candidate position per cell");
    t.add("place_sectors", place.sectors, "", Range::between(8, 720), "place profile: sectors of azimuth");
    t.add("place_range_m", place.max_range_m, "m", Range::above(0), "place profile: farthest range kept");
    t.add("place_band_centres_m", place.band_centres_m, "m", Range::any(),
          "place profile: its horizontal bands, heights of their middles relative to the camera");
    t.add("place_band_offsets_m", place.band_offsets_m, "m", Range::any(),
          "place profile of the map: heights of its rays relative to a band's middle");
    t.add("place_band_half_m", place.band_half_m, "m", Range::above(0),
          "place profile of a query: a band holds its points within this of the band's middle");
    t.add("place_hit_m", place.hit_m, "m", Range::above(0), "place profile of the map: a ray hits this near a point");
    t.add("place_cost_truncation_m", place.cost_truncation_m, "m", Range::above(0),
          "profile comparison: range differences truncated here");
    t.add("retrieval_places", retrieval_places, "", Range::atLeast(1), "places retrieved per query");
    t.add("retrieval_radius_m", retrieval_radius_m, "m", Range::atLeast(0),
          "coarse search: candidate positions this near (horizontally) a retrieved place");
    t.add("retrieval_height_m", retrieval_height_m, "m", Range::atLeast(0), "coarse search: and this near in height");
    t.add("retrieval_yaw_margin_deg", retrieval_yaw_margin_deg, "deg", Range::between(0, 180),
          "coarse search: headings this near a retrieved place's");
    t.add("place_query_depth_m", place_query_depth_m, "m", Range::above(0),
          "place profile of a stereo pair: its points up to this depth (at least max_depth_m)");
    t.add("retrieval_min_sectors", retrieval_min_sectors, "", Range::atLeast(1),
          "on a large map, a query covering fewer profile cells is not localized (the next frame is asked)");
}

void GeometricLocalizationOptions::check(const std::string& input) const
{
    const std::string s = "GeometricLocalization";
    const auto key = [&](const char* k) { return input + ": " + core::iniKeyName(s, k); };
    checkRanges(input, s);
    stereo.check(input, s);
    core::require(!heights_m.empty(), key("heights_m"), "needs at least one height");
    core::require(region.empty() || (region.size() == 4 && region[0] < region[2] && region[1] < region[3]),
                  key("region"), "must be empty or [xmin ymin xmax ymax] with xmin < xmax, ymin < ymax");
    core::require(!refine_truncations_m.empty(), key("refine_truncations_m"), "needs at least one truncation");
    place.check(input, s);
}

}  // namespace quasiloc::reloc
