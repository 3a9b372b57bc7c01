#include "rawlog_entries.h"

#include <mrpt/obs/CAction.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CObservation.h>
#include <mrpt/obs/CSensoryFrame.h>

#include <algorithm>
#include <cmath>
#include <quasiloc/core/error.h>

namespace quasiloc::dataset::detail
{
namespace
{
/** MRPT's exception text is several lines with source locations: one line, bounded. */
std::string compactMessage(const std::string& what)
{
    std::string s;
    for (char c : what.substr(0, 400)) s += (c == '\n' || c == '\r' || c == '\t') ? ' ' : c;
    return s;
}

IsolatedObjectReader::Options isolatedOptions(double timeout_s)
{
    IsolatedObjectReader::Options o;
    o.timeout_ms = int(std::clamp(std::isnan(timeout_s) ? 10.0 : timeout_s, 0.001, 3600.0) * 1000);
    return o;
}
}  // namespace

RawlogEntries::RawlogEntries(const std::string& path, double mrpt_object_timeout_s)
    : path_(path), stream_(file_), reader_(stream_, path), isolated_(isolatedOptions(mrpt_object_timeout_s))
{
    core::require(file_.open(path), path, "cannot open rawlog");
}

bool RawlogEntries::next(std::vector<RawlogObservation>& out)
{
    out.clear();
    for (;;)
    {
        const Kind kind = readTopLevel(out);
        if (kind == Kind::End) return false;
        if (kind == Kind::Observation) return true;
        out.clear();  // a skipped object (CRawlog reads it and drops it)
        if (kind == Kind::ActionCollection) break;
    }
    for (;;)
    {
        const Kind kind = readTopLevel(out);
        if (kind == Kind::SensoryFrame) return true;
        out.clear();
        if (kind == Kind::End)
        {
            // CRawlog ends there too (MRPT's own sample rawlogs do): the action is dropped, the file is not an error.
            ended_after_action_ = true;
            return false;
        }
    }
}

RawlogEntries::Kind RawlogEntries::readTopLevel(std::vector<RawlogObservation>& out)
{
    reader_.startEntry(next_entry_);
    const auto header = readObjectHeader(reader_, true);
    if (!header) return Kind::End;
    ++next_entry_;
    if (header->id == CLASS_ID(mrpt::obs::CSensoryFrame))
    {
        readSensoryFrame(*header, out);
        return Kind::SensoryFrame;
    }
    if (header->id == CLASS_ID(mrpt::obs::CActionCollection))
    {
        readActionCollection(*header);
        return Kind::ActionCollection;
    }
    return readObject(*header, out) ? Kind::Observation : Kind::Other;
}

bool RawlogEntries::readObject(const ObjectHeader& header, std::vector<RawlogObservation>& out)
{
    if (isParsedClass(header.id))
    {
        auto stored = parseKnownObject(reader_, header);
        if (!stored) return false;
        RawlogObservation o;
        o.entry = reader_.entry();
        o.class_name = header.id->className;
        o.timestamp = stored->timestamp;
        if (stored->stereo) o.stereo = std::make_shared<const StoredStereo>(std::move(*stored->stereo));
        if (stored->imu) o.imu = std::make_shared<const StoredImu>(*stored->imu);
        out.push_back(std::move(o));
        return true;
    }
    return readUnparsedObject(header, out);
}

bool RawlogEntries::readUnparsedObject(const ObjectHeader& header, std::vector<RawlogObservation>& out)
{
    // MRPT reads it (header included) in a child process, where a corrupt object can allocate, crash or exit
    // without harm to this one (isolated_object_reader.h).
    const std::string object = "the object of class " + header.class_name + " (at byte " +
                               std::to_string(stream_.getPosition() - header.raw.size()) + ")";
    stream_.pushBack(header.raw);
    const IsolatedObject obj = isolated_.read(stream_);
    if (obj.truncated && stream_.corrupt())
        reader_.fail("the gz-compressed data is corrupt (zlib cannot decompress it) inside " + object);
    if (obj.truncated)
        reader_.fail("truncated: the file ends inside " + object + " (MRPT: " + compactMessage(obj.error) + ")");
    if (!obj.error.empty()) reader_.fail("MRPT could not read " + object + ": " + compactMessage(obj.error));
    if (!obj.is_observation) return false;
    RawlogObservation o;
    o.entry = reader_.entry();
    o.class_name = obj.class_name;
    o.timestamp = obj.timestamp;
    out.push_back(std::move(o));
    return true;
}

void RawlogEntries::readSensoryFrame(const ObjectHeader& header, std::vector<RawlogObservation>& out)
{
    // CSensoryFrame versions 0 to 2: [uint32 ID (v < 2)] [uint64 timestamp of all observations (v0)] uint32 count,
    // then the observations. No reserve(): the count is trusted only as the objects arrive.
    FieldReader::Scope scope(reader_, header.class_name);
    if (header.version > 2) failUnsupportedVersion(reader_, header, "0 to 2");
    if (header.version < 2) reader_.pod<std::uint32_t>("ID");
    std::optional<mrpt::Clock::time_point> frame_time;
    if (header.version == 0)
        frame_time = mrpt::Clock::time_point(mrpt::Clock::duration(reader_.pod<std::int64_t>("timestamp")));
    const auto count = reader_.pod<std::uint32_t>("observation count");
    for (std::uint32_t i = 0; i < count; ++i)
    {
        FieldReader::Scope item(reader_, "observation " + std::to_string(i));
        const auto obs_header = readObjectHeader(reader_, false);
        // MRPT reads each as a CObservation; any other class leaves a null pointer in the frame, which CRawlog's
        // users dereference. Checked before anything reads the object.
        if (!obs_header->id->derivedFrom(CLASS_ID(mrpt::obs::CObservation)))
            reader_.fail("object of class " + obs_header->class_name + " is not an observation");
        readObject(*obs_header, out);
        if (frame_time) out.back().timestamp = *frame_time;
    }
    readEndFlag(reader_);
}

void RawlogEntries::readActionCollection(const ObjectHeader& header)
{
    // CActionCollection version 0: uint32 count, then the actions (read by MRPT: we do not parse any action
    // class; the reader does not use them). No reserve(), unlike MRPT's resize(count).
    FieldReader::Scope scope(reader_, header.class_name);
    if (header.version != 0) failUnsupportedVersion(reader_, header, "0");
    const auto count = reader_.pod<std::uint32_t>("action count");
    std::vector<RawlogObservation> ignored;
    for (std::uint32_t i = 0; i < count; ++i)
    {
        FieldReader::Scope item(reader_, "action " + std::to_string(i));
        const auto action_header = readObjectHeader(reader_, false);
        if (!action_header->id->derivedFrom(CLASS_ID(mrpt::obs::CAction)))
            reader_.fail("object of class " + action_header->class_name + " is not an action");
        readObject(*action_header, ignored);
        ignored.clear();
    }
    readEndFlag(reader_);
}

}  // namespace quasiloc::dataset::detail
