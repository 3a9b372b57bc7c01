// The place retrieval stage of the geometric localizer (geometric_localizer.h, step 1b): its places (a places_file
// read and checked when the localizer is made; else built at the first search that needs them), and which candidate
// positions and headings a query's retrieved places leave to the coarse search.
#include <quasiloc/core/error.h>
#include <quasiloc/reloc/geometric_localizer.h>

#include <chrono>
#include <cmath>
#include <iostream>

namespace quasiloc::reloc
{
std::vector<Eigen::Vector3f> placePositions(const std::vector<Eigen::Vector3d>& positions,
                                            const GeometricLocalizationOptions& o)
{
    std::vector<Eigen::Vector3f> places;
    for (size_t i : selectPlaces(positions, o.place_spacing_m)) places.push_back(positions[i].cast<float>());
    return places;
}

void GeometricLocalizer::setUpPlaces(const map::LidarMap& map, const std::string& input)
{
    const bool large = positions_.size() > size_t(options_.retrieval_min_positions);
    retrieval_ = large || !options_.places_file.empty();
    if (!retrieval_) return;
    map_fingerprint_ = MapFingerprint::of(map);
    if (options_.places_file.empty()) return;  // built when first needed (buildPlaces)
    const auto t0 = std::chrono::steady_clock::now();
    const std::vector<Eigen::Vector3f> places = placePositions(positions_, options_);
    const MapFingerprint& fingerprint = map_fingerprint_;
    const std::string& file = options_.places_file;
    places_ = std::make_unique<PlaceIndex>(PlaceIndex::load(file));
    const PlaceIndex& p = *places_;
    core::require(p.map == fingerprint, file,
                  "built for another map (" + p.map.text() + "; " + input + ": " + fingerprint.text() + ")");
    core::require(p.selection == ShardSelection{}, file,
                  "is shard " + p.selection.text() + ", not a whole place file (merge the shards first)");
    core::require(p.descriptor == options_.place, file,
                  "built with other place_ options of [GeometricLocalization] than this run's");
    bool same = p.total_places == places.size() && p.size() == places.size();
    for (size_t i = 0; same && i < places.size(); ++i) same = (p.positions[i] - places[i]).norm() < 1e-4f;
    core::require(same, file,
                  "its " + std::to_string(p.size()) + " places are not this run's " + std::to_string(places.size()) +
                      " (other candidate or place_spacing_m options)");
    places_build_s_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void GeometricLocalizer::buildPlaces() const
{
    const auto t0 = std::chrono::steady_clock::now();
    places_ = std::make_unique<PlaceIndex>(buildPlaceIndex(*field_, placePositions(positions_, options_),
                                                           options_.place, map_fingerprint_, ShardSelection{}, 32.0));
    places_build_s_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

const PlaceIndex* GeometricLocalizer::places() const
{
    if (!retrieval_) return nullptr;
    std::call_once(places_once_, [this] {
        if (!places_) buildPlaces();
    });
    return places_.get();
}

std::vector<RetrievedPlace> GeometricLocalizer::retrieve(const std::vector<Eigen::Vector3f>& points_cam,
                                                         const Eigen::Vector3d& up_cam, const SearchSphere* near,
                                                         size_t top_k) const
{
    const PlaceIndex* places = this->places();
    if (!places) return {};
    const Eigen::Matrix3d R_level =
        Eigen::Quaterniond::FromTwoVectors(up_cam.normalized(), Eigen::Vector3d::UnitZ()).toRotationMatrix();
    const std::vector<float> query = queryProfile(points_cam, R_level.cast<float>(), places->descriptor);
    if (int(coveredSectors(query).size()) < options_.retrieval_min_sectors) return {};
    RetrievalRequest request;
    request.top_k = top_k > 0 ? top_k : size_t(options_.retrieval_places);
    const int sectors = places->descriptor.sectors;
    if (near)
    {
        request.admitted.resize(places->size());
        for (size_t i = 0; i < places->size(); ++i)
            request.admitted[i] = (places->positions[i].cast<double>() - near->centre).norm() <= near->radius_m;
        if (near->R_world_cam)
        {
            SearchSphere wider = *near;
            wider.heading_bound_deg += options_.retrieval_yaw_margin_deg;
            request.shift_admitted.resize(size_t(sectors));
            for (int s = 0; s < sectors; ++s)
                request.shift_admitted[size_t(s)] = wider.headingAdmits(
                    Eigen::AngleAxisd(2 * M_PI * s / sectors, Eigen::Vector3d::UnitZ()).toRotationMatrix() * R_level);
        }
    }
    return retrievePlaces(*places, query, request, float(options_.place.cost_truncation_m));
}

std::vector<std::vector<bool>> GeometricLocalizer::retrievedYaws(const std::vector<size_t>& searched,
                                                                 const std::vector<RetrievedPlace>& retrieved) const
{
    const int yaws = options_.num_yaws, sectors = places()->descriptor.sectors;
    const double step = 2 * M_PI / yaws, margin = options_.retrieval_yaw_margin_deg * M_PI / 180;
    // The coarse yaws near each retrieved place's heading: those within the margin, and the nearest one always.
    std::vector<std::vector<bool>> place_yaws(retrieved.size(), std::vector<bool>(size_t(yaws), false));
    for (size_t j = 0; j < retrieved.size(); ++j)
    {
        const double yaw = retrieved[j].yawRad(sectors);
        for (int k = 0; k < yaws; ++k)
            place_yaws[j][size_t(k)] = std::abs(std::remainder(step * k - yaw, 2 * M_PI)) <= margin;
        place_yaws[j][size_t(std::lround(yaw / step)) % size_t(yaws)] = true;
    }
    std::vector<std::vector<bool>> out(searched.size(), std::vector<bool>(size_t(yaws), false));
    const double r2 = options_.retrieval_radius_m * options_.retrieval_radius_m;
    for (size_t j = 0; j < retrieved.size(); ++j)
    {
        const Eigen::Vector3d c = places()->positions[retrieved[j].place].cast<double>();
        for (size_t i = 0; i < searched.size(); ++i)
        {
            const Eigen::Vector3d& p = positions_[searched[i]];
            if ((p - c).head<2>().squaredNorm() > r2 || std::abs(p.z() - c.z()) > options_.retrieval_height_m) continue;
            for (int k = 0; k < yaws; ++k)
                if (place_yaws[j][size_t(k)]) out[i][size_t(k)] = true;
        }
    }
    return out;
}

}  // namespace quasiloc::reloc
