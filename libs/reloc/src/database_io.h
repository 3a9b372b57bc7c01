#pragma once
// What the database file and a shard file (database.cpp, database_shard.cpp) store alike: a view, and the camera and
// [Features] options as INI text. The same bytes in both, so a merged database stores exactly what a
// single-process build stores.
#include <mrpt/serialization/CArchive.h>

#include <functional>
#include <quasiloc/reloc/database.h>
#include <string>

namespace quasiloc::reloc::detail
{
void writeView(mrpt::serialization::CArchive& out, const DatabaseView& v);
/** std::runtime_error for inconsistent array sizes. `with_words`: the view has its words (a database view); a
 *  shard's view has none yet (they come from the vocabulary the merge trains). */
DatabaseView readView(mrpt::serialization::CArchive& in, bool with_words);

/** The camera model and the feature options, each as the INI text MRPT writes for it. */
void writeCameraAndFeatures(mrpt::serialization::CArchive& out, const core::CameraModel& camera,
                            const frontend::FeatureOptions& features);
void readCameraAndFeatures(mrpt::serialization::CArchive& in, core::CameraModel& camera,
                           frontend::FeatureOptions& features);

/** Writes a gz-compressed archive to `path`, all or nothing (a temporary renamed when `write` has finished);
 *  InputError naming `path` when it cannot be opened or a write fails. */
void writeArchiveAtomically(const std::string& path, const std::function<void(mrpt::serialization::CArchive&)>& write);

}  // namespace quasiloc::reloc::detail
