#pragma once
// Outputs that appear only when complete. A program writes every output file or folder under a
// temporary name next to its final place; commit() renames them all into place; if the program fails
// (exception) before commit(), the destructor removes the temporaries, so no half-written output is left.
// A killed program (SIGKILL, power aside) leaves its temporaries, ".<name>.tmp-<pid>-<random>": hidden, never taken
// for an output, and removed by the next program that stages the same output once that pid no longer runs.
// commit() renames the last registered output first, so the first one (register the main output first) appears
// last: when it is there, every other output of the run is too (docs/reliability.md).
#include <string>
#include <vector>

namespace quasiloc::core
{
class StagedOutputs
{
   public:
    StagedOutputs() = default;
    StagedOutputs(const StagedOutputs&) = delete;
    StagedOutputs& operator=(const StagedOutputs&) = delete;
    ~StagedOutputs();

    /** Registers an output and returns the temporary path to write it to (same folder, so rename is atomic).
     *  Creates the parent folder if needed. For a folder output, the temporary folder is created. */
    std::string addFile(const std::string& final_path);
    std::string addFolder(const std::string& final_path);

    /** Replaces any existing final outputs with the temporaries, the last registered first. A file is replaced
     *  atomically (rename); a folder is moved aside first (absent for a moment, never partial). */
    void commit();

   private:
    struct Entry
    {
        std::string tmp, final;
    };
    std::vector<Entry> entries_;
    bool committed_ = false;
};

/** Writes `content` to `path` atomically (temporary file + rename). */
void writeTextFileAtomically(const std::string& path, const std::string& content);

}  // namespace quasiloc::core
