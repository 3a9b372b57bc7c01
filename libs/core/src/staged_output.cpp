#include <filesystem>
#include <fstream>
#include <quasiloc/core/error.h>
#include <quasiloc/core/staged_output.h>
#include <random>

namespace fs = std::filesystem;

namespace quasiloc::core
{
namespace
{
std::string temporaryNameFor(const std::string& final_path)
{
    static std::mt19937_64 rng{std::random_device{}()};
    const fs::path p(final_path);
    char suffix[32];
    std::snprintf(suffix, sizeof(suffix), ".tmp-%08llx", static_cast<unsigned long long>(rng() & 0xffffffffULL));
    return (p.parent_path() / ("." + p.filename().string() + suffix)).string();
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
    entries_.push_back({temporaryNameFor(final_path), final_path});
    return entries_.back().tmp;
}

std::string StagedOutputs::addFolder(const std::string& final_path)
{
    require(!final_path.empty(), "output path", "is empty");
    ensureParent(final_path);
    entries_.push_back({temporaryNameFor(final_path), final_path});
    std::error_code ec;
    fs::create_directories(entries_.back().tmp, ec);
    require(!ec, entries_.back().tmp, "cannot create temporary output folder: " + ec.message());
    return entries_.back().tmp;
}

void StagedOutputs::commit()
{
    for (const auto& e : entries_)
    {
        require(fs::exists(e.tmp), e.final, "output was registered but never written");
        std::error_code ec;
        if (fs::exists(e.final)) fs::remove_all(e.final, ec);
        require(!ec, e.final, "cannot replace existing output: " + ec.message());
        fs::rename(e.tmp, e.final, ec);
        require(!ec, e.final, "cannot move output into place: " + ec.message());
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
