#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/obs/CObservationImage.h>
#include <mrpt/obs/CObservationStereoImages.h>
#include <mrpt/obs/CRawlog.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/system/CTimeLogger.h>

#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <optional>
#include <quasiloc/core/error.h>
#include <quasiloc/core/staged_output.h>
#include <quasiloc/dataset/ground_truth.h>
#include <quasiloc/dataset/rawlog_writer.h>
#include <quasiloc/dataset/timestamps.h>
#include <quasiloc/quasi/provenance_check.h>
#include <quasiloc/quasi/quasi_renderer.h>
#include <quasiloc/quasi/rawlog_quasi.h>

namespace fs = std::filesystem;

namespace quasiloc::quasi
{
namespace
{
constexpr const char* kSection = "[RawlogQuasi]";

/** The output being written: rawlog stream, images folder, optional PNG folder, all staged. */
struct Output
{
    core::StagedOutputs staged;  // declared first: destroyed last, after the stream is closed
    std::string tmp_rawlog, tmp_images, tmp_png;
    mrpt::io::CFileGZOutputStream stream;

    void write(const mrpt::serialization::CSerializable& obj)
    {
        auto arch = mrpt::serialization::archiveFrom(stream);
        arch << obj;
    }
};

/** Copies an external image of an input observation into the output's images folder (same relative name). */
void copyExternalImage(const mrpt::img::CImage& img, const std::string& input_images, const std::string& out_images)
{
    if (!img.isExternallyStored()) return;
    const fs::path rel(img.getExternalStorageFile());
    const fs::path src = rel.is_absolute() ? rel : fs::path(input_images) / rel;
    core::require(fs::is_regular_file(src), src.string(), "external image of the input rawlog not found");
    const fs::path dst = fs::path(out_images) / rel.filename();
    fs::copy_file(src, dst, fs::copy_options::overwrite_existing);
}

cv::Mat leftImage(const mrpt::obs::CObservationStereoImages& obs, const std::string& input_images)
{
    if (!obs.imageLeft.isExternallyStored()) return obs.imageLeft.asCvMat<cv::Mat>(mrpt::img::DEEP_COPY);
    const fs::path rel(obs.imageLeft.getExternalStorageFile());
    const fs::path src = rel.is_absolute() ? rel : fs::path(input_images) / rel;
    cv::Mat img = cv::imread(src.string(), cv::IMREAD_UNCHANGED);
    core::require(!img.empty(), src.string(), "cannot read the left image");
    return img;
}

/** Everything needed per stereo frame. */
struct Context
{
    const RawlogQuasiOptions& o;
    const QuasiOptions& qo;
    const map::LidarMap& map;
    QuasiRenderer& renderer;
    Output& out;
    std::string input_images;
    std::optional<dataset::GroundTruthFile> gt;
    RawlogQuasiResult& result;
    mrpt::system::CTimeLogger& timer;
    size_t frames_with_quasi = 0;
    double render_ms_sum = 0;
    QuasiImage q{};  ///< reused: render() keeps its Mats when the size matches (no image-sized allocation per frame)
};

void handleStereo(Context& c, const mrpt::obs::CObservationStereoImages& stereo)
{
    copyExternalImage(stereo.imageLeft, c.input_images, c.out.tmp_images);
    if (stereo.hasImageRight) copyExternalImage(stereo.imageRight, c.input_images, c.out.tmp_images);
    if (stereo.hasImageDisparity) copyExternalImage(stereo.imageDisparity, c.input_images, c.out.tmp_images);
    c.out.write(stereo);
    ++c.result.stereo_frames;

    const mrpt::poses::CPose3D T_body_left(stereo.cameraPose);
    if (!c.gt) c.gt = dataset::readGroundTruthCam0(c.o.groundtruth, T_body_left);
    const std::int64_t t_ns = dataset::mrptTimeToNs(stereo.timestamp);
    const auto T_world_cam0 = dataset::poseAt(c.gt->T_world_cam0, dataset::nsToSeconds(t_ns), c.o.max_gt_dt_s);
    if (!T_world_cam0)
    {
        ++c.result.frames_without_pose;
        return;
    }
    // The raw (distorted) left camera: the quasi-image lives in the stored left image's pixel geometry.
    const core::CameraModel camera = core::CameraModel::fromTCamera(stereo.leftCamera);
    QuasiImage& q = c.q;
    c.renderer.render(*T_world_cam0, camera, q);
    const RenderStats& st = q.stats;
    c.timer.registerUserMeasure("quasi.culling", st.ms_culling * 1e-3);
    c.timer.registerUserMeasure("quasi.projection", st.ms_projection * 1e-3);
    c.timer.registerUserMeasure("quasi.completion", st.ms_completion * 1e-3);
    c.timer.registerUserMeasure("quasi.encoding", st.ms_encoding * 1e-3);
    c.render_ms_sum += st.msTotal();
    c.result.max_render_ms = std::max(c.result.max_render_ms, st.msTotal());

    const std::string name = c.o.sensor_label + "_" + std::to_string(t_ns) + ".png";
    core::require(cv::imwrite((fs::path(c.out.tmp_images) / name).string(), q.bgr), name, "cannot write PNG");
    mrpt::obs::CObservationImage obs;
    obs.sensorLabel = c.o.sensor_label;
    obs.timestamp = stereo.timestamp;
    obs.cameraParams = stereo.leftCamera;
    obs.cameraPose = T_body_left;
    obs.image.setExternalStorage(name);
    c.out.write(obs);
    ++c.result.quasi_images;

    const ProvenanceCheck check = checkProvenance(c.map, q);
    c.result.max_sparse_error_px = std::max(c.result.max_sparse_error_px, check.max_sparse_px);
    c.result.max_completed_error_px = std::max(c.result.max_completed_error_px, check.max_completed_px);

    if (!c.o.png_dir.empty() && c.frames_with_quasi++ % size_t(c.o.png_every) == 0)
    {
        const cv::Mat camera_image = leftImage(stereo, c.input_images);
        const cv::Mat overlay = drawProvenanceOverlay(camera_image, c.map, q, c.qo.completion_radius_px);
        const std::string base = (fs::path(c.out.tmp_png) / std::to_string(t_ns)).string();
        core::require(cv::imwrite(base + "_quasi.png", q.bgr) && cv::imwrite(base + "_quasi_gray.png", q.gray) &&
                          cv::imwrite(base + "_triple.png", makeTriple(camera_image, q, overlay)),
                      c.o.png_dir, "cannot write PNGs");
        c.result.pngs_written += 3;
    }
}

void handle(Context& c, const mrpt::obs::CObservation::Ptr& obs)
{
    if (auto stereo = std::dynamic_pointer_cast<mrpt::obs::CObservationStereoImages>(obs))
        handleStereo(c, *stereo);
    else
    {
        if (auto img = std::dynamic_pointer_cast<mrpt::obs::CObservationImage>(obs))
            copyExternalImage(img->image, c.input_images, c.out.tmp_images);
        c.out.write(*obs);
    }
    ++c.result.observations_copied;
}
}  // namespace

void RawlogQuasiOptions::declare(core::OptionTable& t)
{
    using core::Range;
    t.add("input_rawlog", input_rawlog, "rawlog with CObservationStereoImages; its images in <name>_Images/ beside it");
    t.add("map_file", map_file, "LidarMap file");
    t.add("groundtruth", groundtruth, "TUM of T_world_cam0 (or EuRoC body csv): the render poses");
    t.add("output_rawlog", output_rawlog, "the rawlog written; its images go to <name>_Images/ beside it");
    t.add("max_gt_dt_s", max_gt_dt_s, "s", Range::atLeast(0),
          "a frame without a ground-truth pose this close gets no quasi-image");
    t.add("sensor_label", sensor_label, "sensorLabel of the CObservationImage quasi-images");
    t.add("png_dir", png_dir, "optional: <t_ns>_quasi.png, _quasi_gray.png and _triple.png per frame in this folder");
    t.add("png_every", png_every, "", Range::atLeast(1), "PNGs for every n-th frame with a quasi-image");
    t.add("max_frames", max_frames, "", Range::atLeast(0), "0 = all stereo frames; N = stop after N");
}

void RawlogQuasiOptions::check(const std::string& input) const
{
    checkRanges(input + " " + kSection);
    auto key = [&](const char* k) { return input + " " + kSection + " " + k; };
    core::require(!input_rawlog.empty(), key("input_rawlog"), "is empty");
    core::require(fs::is_regular_file(input_rawlog), key("input_rawlog"), "'" + input_rawlog + "' does not exist");
    core::require(!map_file.empty(), key("map_file"), "is empty");
    core::require(fs::is_regular_file(map_file), key("map_file"), "'" + map_file + "' does not exist");
    core::require(!groundtruth.empty(), key("groundtruth"), "is empty: give the TUM file of T_world_cam0");
    core::require(fs::is_regular_file(groundtruth), key("groundtruth"), "'" + groundtruth + "' does not exist");
    core::require(!output_rawlog.empty(), key("output_rawlog"), "is empty");
    core::require(fs::absolute(output_rawlog) != fs::absolute(input_rawlog), key("output_rawlog"),
                  "is the input rawlog");
    core::require(!sensor_label.empty(), key("sensor_label"), "is empty");
}

RawlogQuasiResult runRawlogQuasi(const RawlogQuasiOptions& o, const QuasiOptions& qo,
                                 const std::string& effective_config)
{
    o.check("rawlog-quasi");
    qo.check("rawlog-quasi");
    const map::LidarMap map = map::LidarMap::load(o.map_file);
    QuasiRenderer renderer(map, qo);

    RawlogQuasiResult result;
    mrpt::system::CTimeLogger timer(true, "rawlog-quasi");
    Output out;
    out.tmp_rawlog = out.staged.addFile(o.output_rawlog);
    out.tmp_images = out.staged.addFolder(dataset::rawlogImagesFolder(o.output_rawlog));
    if (!o.png_dir.empty()) out.tmp_png = out.staged.addFolder(o.png_dir);
    const fs::path out_path(o.output_rawlog);
    const std::string config_path =
        (out_path.parent_path() / (out_path.stem().string() + "_rawlog-quasi.ini")).string();
    core::writeTextFileAtomically(out.staged.addFile(config_path), effective_config);
    core::require(out.stream.open(out.tmp_rawlog, 1), o.output_rawlog, "cannot open for writing");

    mrpt::io::CFileGZInputStream in;
    core::require(in.open(o.input_rawlog), o.input_rawlog, "cannot open");
    auto arch = mrpt::serialization::archiveFrom(in);
    Context c{o, qo, map, renderer, out, dataset::rawlogImagesFolder(o.input_rawlog), std::nullopt, result, timer};
    size_t entry = 0, actions = 0;
    while (o.max_frames == 0 || result.stereo_frames < size_t(o.max_frames))
    {
        mrpt::obs::CActionCollection::Ptr action;
        mrpt::obs::CSensoryFrame::Ptr sf;
        mrpt::obs::CObservation::Ptr obs;
        const uint64_t pos_before = in.getPosition();
        if (!mrpt::obs::CRawlog::getActionObservationPairOrObservation(arch, action, sf, obs, entry))
        {
            core::require(in.getPosition() == pos_before, o.input_rawlog,
                          "corrupt or truncated rawlog at entry " + std::to_string(entry));
            break;
        }
        if (obs) handle(c, obs);
        if (sf)
            for (const auto& so : *sf) handle(c, so);
        actions += action ? 1 : 0;
    }
    core::require(result.stereo_frames > 0, o.input_rawlog, "holds no CObservationStereoImages");
    if (actions) result.warnings.push_back(std::to_string(actions) + " action collections dropped (odometry)");
    if (result.frames_without_pose)
        result.warnings.push_back(std::to_string(result.frames_without_pose) +
                                  " stereo frames without a ground-truth pose within max_gt_dt_s: no quasi-image");
    if (result.quasi_images) result.mean_render_ms = c.render_ms_sum / double(result.quasi_images);
    out.stream.close();
    out.staged.commit();
    result.timing_table = timer.getStatsAsText();
    timer.clear(true);  // the table is returned; nothing to dump at destruction
    timer.disable();
    return result;
}

}  // namespace quasiloc::quasi
