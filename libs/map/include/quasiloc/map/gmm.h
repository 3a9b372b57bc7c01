#pragma once
// GMMLoc Gaussian-mixture maps (.gmm): a room described by Gaussian components fitted to a laser scan
// (the EuRoC Vicon rooms: data/euroc/maps/gmm/v1.gmm, v2.gmm). gmm_surface.h turns one into a LidarMap.
//
// The .gmm files are NOT a single GMMProto message: GMMLoc writes them as a varint component count
// followed by length-delimited ComponentProto messages (varint length + message bytes), each
//   ComponentProto { optional bool is_degenerated = 1; optional bool is_salient = 2;
//                    repeated double mean = 3 [packed]; repeated double covariance = 4 [packed]; }
// We decode the protobuf wire format ourselves (varints, fixed64 doubles, packed and unpacked repeated
// fields, unknown fields skipped) rather than pulling in libprotobuf for a 40-line format.
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

namespace quasiloc::map
{
struct GmmComponent
{
    bool is_degenerated = false;  ///< GMMLoc: a flat (planar) component, smallest eigenvalue clamped
    bool is_salient = false;
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
};

/** Decodes a GMMLoc .gmm file. InputError naming the file for a missing file, a truncated or malformed
 *  message, a component without 3 means / 9 covariances, or a count that disagrees with the components. */
std::vector<GmmComponent> readGmmFile(const std::string& path);
/** Same, from the bytes of a file; `input` names them in errors. */
std::vector<GmmComponent> decodeGmm(const std::vector<uint8_t>& bytes, const std::string& input);

}  // namespace quasiloc::map
