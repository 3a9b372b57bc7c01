#pragma once
// The object level of the validating rawlog reader: MRPT 2.5.8's archive layout of the classes openRawlog reads
// (CObservationStereoImages, CObservationIMU and their members CImage, TCamera, CPose3DQuat, CPose3D), parsed by
// our code, field by field, from the bytes. The layouts are those of MRPT's serializeFrom() of each class
// (libs/obs, libs/img, libs/poses of MRPT 2.5.8); every version noted below reads as MRPT reads it. Older versions
// (written by MRPT before about 1.0) are rejected with an InputError rather than guessed.
#include <mrpt/img/TCamera.h>
#include <mrpt/obs/CObservationIMU.h>
#include <mrpt/poses/CPose3DQuat.h>
#include <mrpt/rtti/CObject.h>
#include <mrpt/system/datetime.h>

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "rawlog_bytes.h"

namespace quasiloc::dataset::detail
{
/** Bounds of this reader (no valid rawlog of ours or of MRPT comes near them). */
constexpr size_t kMaxRawlogText = 64 * 1024;            ///< class-free strings: labels, camera and file names
constexpr std::uint64_t kMaxImagePixels = 1ULL << 26;   ///< 67 Mpixel (8192 x 8192)
constexpr std::uint64_t kMaxImageBytes = 256ULL << 20;  ///< pixels or JPEG bytes of one image

/** An object header: class name (resolved through MRPT's class registry, as MRPT resolves it, with or without
 *  its namespace) and the serialization version; `raw` holds the header bytes as read. */
struct ObjectHeader
{
    std::string class_name;
    const mrpt::rtti::TRuntimeClassId* id = nullptr;
    std::uint8_t version = 0;
    std::vector<std::uint8_t> raw;
};

/** Reads a header. Returns nullopt when the stream ends before its first byte and `end_allowed`; any other end is
 *  "truncated". Rejected: MRPT's pre-0.5.5 header format, class names over 120 bytes (as MRPT), a null object
 *  ("nullptr": MRPT hands a null pointer to its caller, which CRawlog dereferences) and unregistered classes. */
std::optional<ObjectHeader> readObjectHeader(FieldReader& r, bool end_allowed);

/** The end flag (0x88) MRPT writes after each object's data. */
void readEndFlag(FieldReader& r);

/** InputError: the header's serialization version is not one this reader reads (`supported`, e.g. "1 to 4"). */
[[noreturn]] void failUnsupportedVersion(FieldReader& r, const ObjectHeader& h, const char* supported);

/** An mrpt::img::CImage as stored, not decoded yet (embedded JPEGs are decoded only for the frames used). */
struct StoredImage
{
    enum class Kind
    {
        Empty,     ///< no pixels (a 0xN image, or a version-100 image without external file)
        Raw,       ///< `bytes`: rows of `width` x `height` pixels of OpenCV type `cv_type`
        Jpeg,      ///< `bytes` is a JPEG file
        External,  ///< `external_file`, relative to the rawlog's images folder unless absolute
    };
    Kind kind = Kind::Empty;
    int width = 0, height = 0, cv_type = 0;
    std::vector<std::uint8_t> bytes;
    std::string external_file;
};

/** The fields of a CObservationStereoImages that the reader uses. */
struct StoredStereo
{
    mrpt::img::TCamera left_camera, right_camera;
    mrpt::poses::CPose3DQuat camera_pose, right_camera_pose;
    StoredImage left, right;
    bool has_right = true;
};

/** The fields of a CObservationIMU that the reader uses. */
struct StoredImu
{
    std::array<bool, mrpt::obs::COUNT_IMU_DATA_FIELDS> present{};
    std::array<double, mrpt::obs::COUNT_IMU_DATA_FIELDS> values{};
};

/** One observation whose class this reader parses. */
struct StoredObservation
{
    mrpt::Clock::time_point timestamp;
    std::optional<StoredStereo> stereo;
    std::optional<StoredImu> imu;
};

/** Whether parseKnownObject() reads objects of this class. */
bool isParsedClass(const mrpt::rtti::TRuntimeClassId* id);

/** The data and end flag of an object whose header was just read, of a class for which isParsedClass() is true.
 *  Returns the observation for CObservationStereoImages and CObservationIMU, nullopt for the others (CImage,
 *  TCamera, CPose3D, CPose3DQuat, read and discarded, as CRawlog discards a top-level object that is neither an
 *  observation nor an action collection). */
std::optional<StoredObservation> parseKnownObject(FieldReader& r, const ObjectHeader& header);

}  // namespace quasiloc::dataset::detail
