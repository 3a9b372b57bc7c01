// StagedOutputs after a kill: the temporaries a dead process left are removed by the next run that stages the same
// output; a live process's are left alone; a folder output replaces an existing one.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <quasiloc/core/staged_output.h>

using namespace quasiloc::core;
namespace fs = std::filesystem;

namespace
{
std::string freshDir(const std::string& name)
{
    const fs::path d = fs::temp_directory_path() / ("quasiloc_" + name + "_" + std::to_string(::getpid()));
    fs::remove_all(d);
    fs::create_directories(d);
    return d.string();
}

/** The pid of a process that has ended (a child that exited and was reaped). */
long deadPid()
{
    const pid_t child = ::fork();
    if (child == 0) ::_exit(0);
    ::waitpid(child, nullptr, 0);
    return long(child);
}

size_t entries(const std::string& dir)
{
    return size_t(std::distance(fs::directory_iterator(dir), fs::directory_iterator()));
}
}  // namespace

TEST(StagedOutputsAfterAKill, LeftoversOfADeadProcessAreRemovedByTheNextRun)
{
    const std::string dir = freshDir("staged_leftovers");
    const std::string dead = std::to_string(deadPid());
    std::ofstream(dir + "/.result.txt.tmp-" + dead + "-0badf00d") << "half";                   // a file
    fs::create_directories(dir + "/.result.txt.tmp-" + dead + "-1badf00d");                    // a folder
    std::ofstream(dir + "/..result.txt.tmp-" + dead + "-2badf00d.tmp-" + dead + "-3") << "x";  // nested staging
    const std::string live = std::to_string(::getppid());
    std::ofstream(dir + "/.result.txt.tmp-" + live + "-4badf00d") << "being written";
    std::ofstream(dir + "/.other.txt.tmp-" + dead + "-5badf00d") << "another output's";
    writeTextFileAtomically(dir + "/result.txt", "full");
    EXPECT_TRUE(fs::exists(dir + "/result.txt"));
    EXPECT_TRUE(fs::exists(dir + "/.result.txt.tmp-" + live + "-4badf00d")) << "a live writer's temporary stays";
    EXPECT_TRUE(fs::exists(dir + "/.other.txt.tmp-" + dead + "-5badf00d")) << "only this output's are removed";
    EXPECT_EQ(entries(dir), 3u);
    fs::remove_all(dir);
}

TEST(StagedOutputsAfterAKill, AFolderOutputReplacesAnExistingOne)
{
    const std::string dir = freshDir("staged_folder");
    for (const char* content : {"one", "two"})
    {
        StagedOutputs out;
        const std::string tmp = out.addFolder(dir + "/images");
        std::ofstream(tmp + "/" + content + ".png") << content;
        out.commit();
    }
    EXPECT_FALSE(fs::exists(dir + "/images/one.png"));
    EXPECT_TRUE(fs::exists(dir + "/images/two.png"));
    EXPECT_EQ(entries(dir), 1u) << "the old folder is removed, no temporary left";
    fs::remove_all(dir);
}
