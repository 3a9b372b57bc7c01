#pragma once
// Helpers for the dataset unit tests (header-only, test code only).
#include <gtest/gtest.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>

#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <quasiloc/core/error.h>
#include <string>

namespace quasiloc::dataset::test
{
inline std::string microEurocFolder() { return std::string(QUASILOC_SHARED_DIR) + "/data/euroc/V1_01_easy_micro"; }
inline std::string eurocCam0Groundtruth()
{
    return std::string(QUASILOC_SHARED_DIR) + "/data/euroc/groundtruth/cam0/V1_01_easy.txt";
}

/** A fresh temporary folder, removed with everything in it at scope exit. */
class TempDir
{
   public:
    TempDir()
    {
        std::string tmpl = (std::filesystem::temp_directory_path() / "quasiloc_dataset_XXXXXX").string();
        if (!mkdtemp(tmpl.data())) throw std::runtime_error("mkdtemp failed");
        path_ = tmpl;
    }
    ~TempDir()
    {
        std::error_code ec;
        std::filesystem::remove_all(path_, ec);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    const std::string& path() const { return path_; }
    std::string operator/(const std::string& name) const { return path_ + "/" + name; }

   private:
    std::string path_;
};

/** Runs f, expects an InputError whose message contains `needle` (e.g. the file name). */
template <typename F>
void expectInputErrorMentioning(F&& f, const std::string& needle)
{
    try
    {
        f();
        ADD_FAILURE() << "expected an InputError mentioning '" << needle << "'";
    }
    catch (const core::InputError& e)
    {
        std::cout << "  expected InputError: " << e.what() << std::endl;
        EXPECT_NE(std::string(e.what()).find(needle), std::string::npos)
            << "message '" << e.what() << "' does not mention '" << needle << "'";
    }
}

/** An action collection with one 2D odometry movement: an action, which MRPT reads in the child process. */
inline mrpt::obs::CActionCollection odometryActions()
{
    mrpt::obs::CActionCollection actions;
    mrpt::obs::CActionRobotMovement2D move;
    move.computeFromOdometry(mrpt::poses::CPose2D(0.1, 0, 0.01), {});
    actions.insert(move);
    return actions;
}

}  // namespace quasiloc::dataset::test
