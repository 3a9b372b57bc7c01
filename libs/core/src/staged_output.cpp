#include <quasiloc/core/error.h>
#include <quasiloc/core/staged_output.h>
#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <filesystem>
#include <fstream>
#include <random>
#include <vector>

namespace fs = std::filesystem;

namespace quasiloc::core
{
namespace
{
// A temporary is ".<name>.tmp-<pid>-<random>" beside <name>: hidden, never an output's name, and it names the
// process that writes it, so that a later run can tell a leftover of a killed process from a live one's.
std::string temporaryNameFor(const std::string& final_path)
{
    static std::mt19937_64 rng{std::random_device{}()};
    const fs::path p(final_path);
    char suffix[48];
    std::snprintf(suffix, sizeof(suffix), ".tmp-%ld-%08llx", static_cast<long>(::getpid()),
                  static_cast<unsigned long long>(rng() & 0xffffffffULL));
    return (p.parent_path() / ("." + p.filename().string() + suffix)).string();
}

/** The process that wrote the temporary `name` of an output called `output_name` (0: not such a temporary). Nested
 *  staging (a staged writer writing to a temporary path) makes "..<name>.tmp-<pid>-<r>.tmp-<pid>-<r>". */
long writerOf(const std::string& name, const std::string& output_name)
{
    if (name.empty() || name[0] != '.') return 0;
    const std::string marker = output_name + ".tmp-";
    const size_t at = name.find(marker);
    if (at == std::string::npos || name.find_first_not_of('.') != at) return 0;
    return std::strtol(name.c_str() + at + marker.size(), nullptr, 10);
}

/** Removes the temporaries of `final_path` left by processes that no longer run (killed before their commit):
 *  a program ignores them and they do not pile up. Another live process's temporaries are left alone. */
void removeLeftovers(const std::string& final_path)
{
    const fs::path p(final_path);
    const fs::path dir = p.parent_path().empty() ? fs::path(".") : p.parent_path();
    // Listed first, removed after: a folder changed while it is read may skip entries (readdir(3)).
    std::error_code ec;
    std::vector<fs::path> leftovers;
    for (const auto& e : fs::directory_iterator(dir, ec))
    {
        const long pid = writerOf(e.path().filename().string(), p.filename().string());
        if (pid > 0 && pid != long(::getpid()) && ::kill(pid_t(pid), 0) != 0 && errno == ESRCH)
            leftovers.push_back(e.path());
    }
    for (const auto& l : leftovers) fs::remove_all(l, ec);
}

void ensureParent(const std::string& path)
{
    const fs::path parent = fs::path(path).parent_path();
    if (parent.empty()) return;
    std::error_code ec;
    fs::create_directories(parent, ec);
    require(!ec, parent.string(), "cannot create output folder: " + ec.message());
}
}  // namespace

StagedOutputs::~StagedOutputs()
{
    if (committed_) return;
    for (const auto& e : entries_)
    {
        std::error_code ec;
        fs::remove_all(e.tmp, ec);
    }
}

std::string StagedOutputs::addFile(const std::string& final_path)
{
    require(!final_path.empty(), "output path", "is empty");
    ensureParent(final_path);
    removeLeftovers(final_path);
    entries_.push_back({temporaryNameFor(final_path), final_path});
    return entries_.back().tmp;
}

std::string StagedOutputs::addFolder(const std::string& final_path)
{
    require(!final_path.empty(), "output path", "is empty");
    ensureParent(final_path);
    removeLeftovers(final_path);
    entries_.push_back({temporaryNameFor(final_path), final_path});
    std::error_code ec;
    fs::create_directories(entries_.back().tmp, ec);
    require(!ec, entries_.back().tmp, "cannot create temporary output folder: " + ec.message());
    return entries_.back().tmp;
}

void StagedOutputs::commit()
{
    for (const auto& e : entries_) require(fs::exists(e.tmp), e.final, "output was registered but never written");
    // The last registered first: the first (a program's main output) appears last, so when it is there, all are.
    for (auto e = entries_.rbegin(); e != entries_.rend(); ++e)
    {
        std::error_code ec;
        if (fs::is_directory(e->final) && !fs::is_symlink(e->final))
        {
            // rename(2) does not replace a folder that has files: the old one is moved aside, then removed.
            const std::string old = temporaryNameFor(e->final);
            fs::rename(e->final, old, ec);
            require(!ec, e->final, "cannot replace existing output: " + ec.message());
            fs::rename(e->tmp, e->final, ec);
            require(!ec, e->final, "cannot move output into place: " + ec.message());
            fs::remove_all(old, ec);
            continue;
        }
        // A file is replaced in one step (rename(2) is atomic): the old or the new one is there, never neither.
        fs::rename(e->tmp, e->final, ec);
        require(!ec, e->final, "cannot move output into place: " + ec.message());
    }
    committed_ = true;
}

void writeTextFileAtomically(const std::string& path, const std::string& content)
{
    StagedOutputs out;
    const std::string tmp = out.addFile(path);
    {
        std::ofstream f(tmp);
        require(f.good(), path, "cannot open for writing");
        f << content;
        f.close();
        require(!f.fail(), path, "write failed");
    }
    out.commit();
}

}  // namespace quasiloc::core
