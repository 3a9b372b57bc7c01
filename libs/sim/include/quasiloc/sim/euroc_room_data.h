#pragma once
// Readers for the two descriptions of the EuRoC Vicon rooms that survive without the Leica scans:
// the GMMLoc Gaussian-mixture maps (maps/gmm/v1.gmm, v2.gmm) and the 3D line maps (maps/lines/*.txt).
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

namespace quasiloc::sim
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

struct LineSegment3D
{
    Eigen::Vector3d a = Eigen::Vector3d::Zero(), b = Eigen::Vector3d::Zero();
};

/** Reads "x1 y1 z1 x2 y2 z2" rows (metres); InputError naming file and line for anything else. */
std::vector<LineSegment3D> readLineSegments(const std::string& path);

}  // namespace quasiloc::sim
