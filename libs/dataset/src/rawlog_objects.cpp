#include "rawlog_objects.h"

#include <mrpt/img/CImage.h>
#include <mrpt/obs/CObservationStereoImages.h>
#include <mrpt/poses/CPose3D.h>

#include <opencv2/core.hpp>
#include <utility>

namespace quasiloc::dataset::detail
{
namespace
{
using mrpt::rtti::TRuntimeClassId;
using Scope = FieldReader::Scope;

const TRuntimeClassId* stereoId() { return CLASS_ID(mrpt::obs::CObservationStereoImages); }
const TRuntimeClassId* imuId() { return CLASS_ID(mrpt::obs::CObservationIMU); }
const TRuntimeClassId* imageId() { return CLASS_ID(mrpt::img::CImage); }
const TRuntimeClassId* cameraId() { return CLASS_ID(mrpt::img::TCamera); }
const TRuntimeClassId* pose3DId() { return CLASS_ID(mrpt::poses::CPose3D); }
const TRuntimeClassId* pose3DQuatId() { return CLASS_ID(mrpt::poses::CPose3DQuat); }

mrpt::Clock::time_point readTimestamp(FieldReader& r)
{
    // MRPT stores the tick count as uint64 and converts it to the clock's int64 representation.
    const auto ticks = r.pod<std::uint64_t>("timestamp");
    return mrpt::Clock::time_point(mrpt::Clock::duration(static_cast<std::int64_t>(ticks)));
}

/** A member object of a fixed class (as CArchive::ReadObject(existing object) reads it: the stored class must be
 *  the member's class), its data read by `body(version)`, then the end flag. */
template <class Body>
auto readMember(FieldReader& r, const char* member, const TRuntimeClassId* expected, Body&& body)
{
    Scope scope(r, member);
    const auto header = readObjectHeader(r, false);
    if (header->id != expected)
        r.fail(std::string("stored class ") + header->class_name + ", expected " + expected->className);
    Scope in_class(r, header->class_name);
    auto value = body(*header);
    readEndFlag(r);
    return value;
}

// --- CPose3DQuat (version 0: x y z qr qx qy qz) and CPose3D (v2: the same 7 doubles; v3: x y z + 3x3 rotation).
mrpt::poses::CPose3DQuat readPose3DQuatData(FieldReader& r, const ObjectHeader& h)
{
    if (h.version != 0) failUnsupportedVersion(r, h, "0");
    // Stored as MRPT stores it, without normalising the quaternion (as CPose3DQuat::serializeFrom).
    mrpt::poses::CPose3DQuat p(mrpt::math::UNINITIALIZED_QUATERNION);
    for (int i = 0; i < 7; ++i) p[i] = r.pod<double>("pose coordinate");
    return p;
}

bool skipPose3DData(FieldReader& r, const ObjectHeader& h)
{
    if (h.version != 2 && h.version != 3) failUnsupportedVersion(r, h, "2 and 3");
    for (int i = 0; i < (h.version == 3 ? 12 : 7); ++i) r.pod<double>("pose coordinate");
    return true;
}

// --- TCamera, versions 4 to 6: focalLengthMeters, dist[5] (v>=3: dist[5..7]), fx fy cx cy, nrows ncols,
// cameraName (v>=5), distortion model as uint8 (v>=6; before: plumb_bob).
mrpt::img::TCamera readCameraData(FieldReader& r, const ObjectHeader& h)
{
    if (h.version < 4 || h.version > 6) failUnsupportedVersion(r, h, "4 to 6");
    mrpt::img::TCamera c;
    c.focalLengthMeters = r.pod<double>("focalLengthMeters");
    c.dist.fill(0);
    for (size_t k = 0; k < 8; ++k) c.dist[k] = r.pod<double>("dist");
    const double fx = r.pod<double>("fx"), fy = r.pod<double>("fy"), cx = r.pod<double>("cx"), cy = r.pod<double>("cy");
    c.setIntrinsicParamsFromValues(fx, fy, cx, cy);
    c.nrows = r.pod<std::uint32_t>("nrows");
    c.ncols = r.pod<std::uint32_t>("ncols");
    if (h.version >= 5) c.cameraName = r.text("cameraName", kMaxRawlogText);
    c.distortion = h.version >= 6 ? static_cast<mrpt::img::DistortionModel>(r.pod<std::uint8_t>("distortion"))
                                  : mrpt::img::DistortionModel::plumb_bob;
    return c;
}

// --- CImage, versions 1 to 9 and 100 (CImage::serializeFrom).
void checkImageSize(FieldReader& r, std::int64_t width, std::int64_t height, std::int64_t bytes_per_pixel)
{
    if (width < 0 || height < 0)
        r.fail("image size " + std::to_string(width) + "x" + std::to_string(height) + " is negative");
    if (std::uint64_t(width) * std::uint64_t(height) > kMaxImagePixels ||
        std::uint64_t(width) * std::uint64_t(height) * std::uint64_t(bytes_per_pixel) > kMaxImageBytes)
        r.fail("image size " + std::to_string(width) + "x" + std::to_string(height) + " is beyond this reader's " +
               std::to_string(kMaxImagePixels) + " pixels or " + std::to_string(kMaxImageBytes) + " bytes");
}

/** A JPEG file stored as its uint32 length and bytes. */
StoredImage readJpegImage(FieldReader& r)
{
    const auto n = r.pod<std::uint32_t>("JPEG length");
    if (n > kMaxImageBytes)
        r.fail("JPEG length of " + std::to_string(n) + " bytes is beyond this reader's " +
               std::to_string(kMaxImageBytes));
    StoredImage img;
    img.kind = StoredImage::Kind::Jpeg;
    img.bytes = r.bytes(n, "JPEG data");
    return img;
}

/** An externally stored image: its file name. */
StoredImage readExternalImage(FieldReader& r)
{
    StoredImage img;
    img.kind = StoredImage::Kind::External;
    img.external_file = r.text("external file name", kMaxRawlogText);
    return img;
}

int cvDepthOf(FieldReader& r, std::int32_t pixel_depth)
{
    // mrpt::img::PixelDepth: D8U, D8S, D16U, D16S, D32S, D32F, D64F (the same order as OpenCV's depths).
    static const int kDepths[] = {CV_8U, CV_8S, CV_16U, CV_16S, CV_32S, CV_32F, CV_64F};
    if (pixel_depth < 0 || pixel_depth > 6) r.fail("pixel depth " + std::to_string(pixel_depth) + " is unknown");
    return kDepths[pixel_depth];
}

StoredImage readGrayPixels(FieldReader& r, std::uint8_t version)
{
    StoredImage img;
    const auto width = r.pod<std::int32_t>("width"), height = r.pod<std::int32_t>("height");
    r.pod<std::int32_t>("origin");
    const auto image_size = r.pod<std::int32_t>("image size");
    const int depth = version >= 9 ? cvDepthOf(r, r.pod<std::int32_t>("pixel depth")) : CV_8U;
    const auto elem = static_cast<std::int64_t>(CV_ELEM_SIZE(CV_MAKETYPE(depth, 1)));
    checkImageSize(r, width, height, elem);
    // MRPT asserts that the stored size is that of the rows it allocated.
    if (std::int64_t(image_size) != std::int64_t(width) * height * elem)
        r.fail("image size field " + std::to_string(image_size) + " does not match " + std::to_string(width) + "x" +
               std::to_string(height) + " pixels of " + std::to_string(elem) + " bytes");
    bool zip = version >= 3;                                   // version 3: always zip
    if (version == 4 && image_size <= 16 * 1024) zip = false;  // version 4: zip above 16 KB
    if (version >= 5) zip = r.flag("zip flag");                // version 5: stored
    if (zip) r.fail("ZIP-compressed image (MRPT 2.5 cannot read it either)");
    img.kind = StoredImage::Kind::Raw;
    img.width = width;
    img.height = height;
    img.cv_type = CV_MAKETYPE(depth, 1);
    img.bytes = r.bytes(size_t(image_size), "gray pixels");
    return img;
}

StoredImage readColourPixels(FieldReader& r, std::uint8_t version)
{
    StoredImage img;
    if (version >= 7)
    {
        const auto width = r.pod<std::int32_t>("width"), height = r.pod<std::int32_t>("height");
        if (width < 0 && height < 0)
        {
            // Version 8: raw BGR rows, the size stored negated.
            if (width == INT32_MIN || height == INT32_MIN) r.fail("image size is INT32_MIN");
            checkImageSize(r, -std::int64_t(width), -std::int64_t(height), 3);
            img.kind = StoredImage::Kind::Raw;
            img.width = -width;
            img.height = -height;
            img.cv_type = CV_8UC3;
            img.bytes = r.bytes(size_t(img.width) * size_t(img.height) * 3, "colour pixels");
            return img;
        }
        if (width < 1 || height < 1)
        {
            checkImageSize(r, width, height, 3);  // rejects a negative size: MRPT would allocate 4e9 rows
            return img;                           // a 0xN image: no data
        }
    }
    return readJpegImage(r);
}

StoredImage readImageData(FieldReader& r, const ObjectHeader& h)
{
    const std::uint8_t v = h.version;
    if (v == 100)  // written by an MRPT without OpenCV: external file or nothing
        return r.flag("external storage flag") ? readExternalImage(r) : StoredImage{};
    if (v == 1) return readJpegImage(r);  // a JPEG only
    if (v < 2 || v > 9) failUnsupportedVersion(r, h, "1 to 9 and 100");
    if (v >= 6 && r.flag("external storage flag")) return readExternalImage(r);
    return r.flag("colour flag") ? readColourPixels(r, v) : readGrayPixels(r, v);
}

// --- CObservationStereoImages, versions 5 and 6.
StoredObservation readStereoData(FieldReader& r, const ObjectHeader& h)
{
    if (h.version != 5 && h.version != 6) failUnsupportedVersion(r, h, "5 and 6");
    StoredObservation o;
    StoredStereo& s = o.stereo.emplace();
    s.camera_pose = readMember(r, "cameraPose", pose3DQuatId(), [&](auto& m) { return readPose3DQuatData(r, m); });
    s.left_camera = readMember(r, "leftCamera", cameraId(), [&](auto& m) { return readCameraData(r, m); });
    s.right_camera = readMember(r, "rightCamera", cameraId(), [&](auto& m) { return readCameraData(r, m); });
    s.left = readMember(r, "imageLeft", imageId(), [&](auto& m) { return readImageData(r, m); });
    bool has_disparity = false;
    if (h.version == 6)
    {
        has_disparity = r.flag("hasImageDisparity");
        s.has_right = r.flag("hasImageRight");
    }
    if (s.has_right) s.right = readMember(r, "imageRight", imageId(), [&](auto& m) { return readImageData(r, m); });
    if (has_disparity) readMember(r, "imageDisparity", imageId(), [&](auto& m) { return readImageData(r, m); });
    o.timestamp = readTimestamp(r);
    s.right_camera_pose =
        readMember(r, "rightCameraPose", pose3DQuatId(), [&](auto& m) { return readPose3DQuatData(r, m); });
    r.text("sensorLabel", kMaxRawlogText);
    return o;
}

// --- CObservationIMU, versions 1 to 4 (v4: fixed arrays; before: std::vector<bool> and std::vector<double>).
StoredObservation readImuData(FieldReader& r, const ObjectHeader& h)
{
    if (h.version < 1 || h.version > 4) failUnsupportedVersion(r, h, "1 to 4");
    constexpr size_t kFields = mrpt::obs::COUNT_IMU_DATA_FIELDS;
    StoredObservation o;
    StoredImu& imu = o.imu.emplace();
    readMember(r, "sensorPose", pose3DId(), [&](auto& m) { return skipPose3DData(r, m); });
    auto count = [&](const char* field) {
        const auto n = r.pod<std::uint32_t>(field);
        // MRPT copies the vector into a fixed array with at(): more than kFields elements is an exception.
        if (n > kFields)
            r.fail(std::string(field) + " is " + std::to_string(n) + ", more than the " + std::to_string(kFields) +
                   " IMU fields");
        return n;
    };
    const size_t n_flags = h.version == 4 ? kFields : count("dataIsPresent length");
    for (size_t i = 0; i < n_flags; ++i) imu.present[i] = r.flag("dataIsPresent");
    o.timestamp = readTimestamp(r);
    const size_t n_values = h.version == 4 ? kFields : count("rawMeasurements length");
    for (size_t i = 0; i < n_values; ++i) imu.values[i] = r.pod<double>("rawMeasurements");
    // Versions 0 and 1 had the yaw and roll rates swapped (an XSens grabber bug), as MRPT corrects.
    if (h.version < 2) std::swap(imu.values[mrpt::obs::IMU_YAW_VEL], imu.values[mrpt::obs::IMU_ROLL_VEL]);
    r.text("sensorLabel", kMaxRawlogText);
    return o;
}
}  // namespace

std::optional<ObjectHeader> readObjectHeader(FieldReader& r, bool end_allowed)
{
    ObjectHeader h;
    std::uint8_t first = 0;
    if (r.readSome(&first, 1) == 0)
    {
        if (end_allowed) return std::nullopt;
        r.fail("truncated: the file ends where an object begins");
    }
    h.raw.push_back(first);
    if (!(first & 0x80)) r.fail("object header in MRPT's format before 0.5.5 (not supported), or a corrupt file");
    const size_t length = first & 0x7F;
    if (length == 0) r.fail("class name of 0 bytes (corrupt file)");
    if (length > 120) r.fail("class name of " + std::to_string(length) + " bytes (MRPT allows 120; corrupt file)");
    std::vector<std::uint8_t> name(length);
    r.readExactly(name.data(), length, "class name");
    h.raw.insert(h.raw.end(), name.begin(), name.end());
    h.class_name.assign(name.begin(), name.end());
    if (h.class_name == "nullptr") r.fail("a null object where an object is expected");
    h.id = mrpt::rtti::findRegisteredClass(h.class_name);
    if (!h.id)
        r.fail("class '" + h.class_name +
               "' is not registered in MRPT (a corrupt file, or a class of an MRPT library this "
               "program does not load)");
    h.version = r.pod<std::uint8_t>("serialization version");
    h.raw.push_back(h.version);
    return h;
}

void failUnsupportedVersion(FieldReader& r, const ObjectHeader& h, const char* supported)
{
    r.fail("serialization version " + std::to_string(h.version) + " of " + h.class_name +
           " is not supported (this reader reads versions " + supported +
           "; older ones come from MRPT before 1.0, newer ones do not exist in MRPT 2.5)");
}

void readEndFlag(FieldReader& r)
{
    const auto flag = r.pod<std::uint8_t>("end flag");
    if (flag != 0x88)
        r.fail("end flag is " + std::to_string(flag) +
               ", not 0x88: the object's data has another length than its "
               "class reads (corrupt file)");
}

bool isParsedClass(const TRuntimeClassId* id)
{
    return id == stereoId() || id == imuId() || id == imageId() || id == cameraId() || id == pose3DId() ||
           id == pose3DQuatId();
}

std::optional<StoredObservation> parseKnownObject(FieldReader& r, const ObjectHeader& h)
{
    Scope scope(r, h.class_name);
    std::optional<StoredObservation> o;
    if (h.id == stereoId())
        o = readStereoData(r, h);
    else if (h.id == imuId())
        o = readImuData(r, h);
    else if (h.id == imageId())
        readImageData(r, h);
    else if (h.id == cameraId())
        readCameraData(r, h);
    else if (h.id == pose3DId())
        skipPose3DData(r, h);
    else if (h.id == pose3DQuatId())
        readPose3DQuatData(r, h);
    else
        r.fail("internal: class " + h.class_name + " is not parsed here");
    readEndFlag(r);
    return o;
}

}  // namespace quasiloc::dataset::detail
