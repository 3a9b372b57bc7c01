#pragma once
// The entry level of the validating rawlog reader (docs/fuzzing.md): reads a rawlog entry by entry as
// mrpt::obs::CRawlog::getActionObservationPairOrObservation does, without letting MRPT deserialize the classes
// that openRawlog uses.
//
// Why: MRPT's deserialization trusts the file. On a corrupt rawlog it allocates what a length field says (strings,
// image sizes up to 3.6e18 bytes), decodes embedded JPEGs with libjpeg's exit(1) error handler, and can spend
// seconds in one read. Our parser (rawlog_objects.h) reads CObservationStereoImages, CObservationIMU, CSensoryFrame
// and their members field by field: every length is bounded and its bytes must arrive before they are kept, every
// size is checked, embedded JPEGs are decoded by OpenCV (embedded_jpeg.h). Errors are InputErrors naming the file,
// the entry, the byte offset and the field.
//
// Classes we do not parse (other observations, which the reader counts and ignores, and the actions of an action
// collection) are read by MRPT, because their bytes have no length prefix and only their own serializeFrom() knows
// where they end. MRPT reads them in a child process (isolated_object_reader.h): whatever a corrupt object makes
// MRPT do there (allocate what a length field says, crash, call exit()) ends the child, and this reader reports an
// InputError naming the file, the entry, the object's byte offset and its class. Rawlogs of quasiloc
// (euroc2rawlog, bag2rawlog, sim-rawlog) hold only the parsed classes and never start a child.
#include <mrpt/io/CFileGZInputStream.h>

#include <memory>
#include <string>
#include <vector>

#include "isolated_object_reader.h"
#include "rawlog_bytes.h"
#include "rawlog_objects.h"

namespace quasiloc::dataset::detail
{
/** One observation of a rawlog: parsed (stereo, IMU) or read by MRPT and only named (any other class). */
struct RawlogObservation
{
    size_t entry = 0;        ///< the top-level object (observation or sensory frame) it came from
    std::string class_name;  ///< MRPT's name of its class
    mrpt::Clock::time_point timestamp;
    std::shared_ptr<const StoredStereo> stereo;  ///< set for CObservationStereoImages
    std::shared_ptr<const StoredImu> imu;        ///< set for CObservationIMU
};

class RawlogEntries
{
   public:
    /** Opens the file (plain or gz); InputError naming it when it cannot. `mrpt_object_timeout_s`: see
     *  FrameSourceOptions. */
    explicit RawlogEntries(const std::string& path, double mrpt_object_timeout_s = 10);

    /** The next observation, or the observations of the next sensory frame, into `out`, following CRawlog's
     *  layouts: a top-level observation is returned alone; an action collection is followed by a sensory frame,
     *  whose observations are returned (objects between them are skipped); any other top-level object (a sensory
     *  frame without an action collection before it, a pose, ...) is skipped. False at the clean end of the file,
     *  which may come after an action collection whose sensory frame is missing, as CRawlog reads it
     *  (endedAfterAction()). A corrupt or truncated entry is an InputError. */
    bool next(std::vector<RawlogObservation>& out);
    /** The file ended after an action collection, before the sensory frame that should follow it. */
    bool endedAfterAction() const { return ended_after_action_; }

   private:
    enum class Kind
    {
        End,
        Observation,
        ActionCollection,
        SensoryFrame,
        Other
    };
    Kind readTopLevel(std::vector<RawlogObservation>& out);
    void readSensoryFrame(const ObjectHeader& header, std::vector<RawlogObservation>& out);
    void readActionCollection(const ObjectHeader& header);
    /** An object whose header was just read: parsed when its class is known, else read by MRPT in the child
     *  process. Appends it to `out` when it is an observation; returns whether it is one. */
    bool readObject(const ObjectHeader& header, std::vector<RawlogObservation>& out);
    bool readUnparsedObject(const ObjectHeader& header, std::vector<RawlogObservation>& out);

    std::string path_;
    mrpt::io::CFileGZInputStream file_;
    RawlogStream stream_;
    FieldReader reader_;
    IsolatedObjectReader isolated_;  // the classes we do not parse
    size_t next_entry_ = 0;
    bool ended_after_action_ = false;
};

}  // namespace quasiloc::dataset::detail
