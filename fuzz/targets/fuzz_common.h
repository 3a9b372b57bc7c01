#pragma once
// What every fuzz target shares. A reader given bad bytes must end in a clean error: core::InputError, or another
// std::exception that the programs catch and report (core::runProgram prints it and exits 1). Anything else is a
// finding that libFuzzer records: a crash or UB (ASan/UBSan abort), a hang (-timeout), a huge allocation
// (-malloc_limit_mb), and also std::bad_alloc / std::length_error, which mean a length field was trusted.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <new>
#include <quasiloc/core/error.h>
#include <stdexcept>
#include <string>
#include <vector>

namespace quasiloc::fuzz
{
/** A folder of this process for readers that only take a path: /dev/shm when present (no disk writes per run). */
inline const std::filesystem::path& scratchDir()
{
    static const std::filesystem::path dir = [] {
        const std::filesystem::path base = std::filesystem::is_directory("/dev/shm") ? "/dev/shm" : "/tmp";
        auto d = base / ("quasiloc-fuzz-" + std::to_string(::getpid()));
        std::filesystem::create_directories(d);
        std::atexit([] {
            std::error_code ec;
            std::filesystem::remove_all(scratchDir(), ec);
        });
        return d;
    }();
    return dir;
}

/** Writes the input to scratchDir()/name (creating sub-folders) and returns the path. */
inline std::string writeInput(const uint8_t* data, size_t size, const std::string& name)
{
    const auto path = scratchDir() / name;
    std::filesystem::create_directories(path.parent_path());
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    return path.string();
}

inline void writeText(const std::string& name, const std::string& text)
{
    writeInput(reinterpret_cast<const uint8_t*>(text.data()), text.size(), name);
}

/** Runs `read` on one input: clean errors pass, a trusted length field aborts (a finding). */
template <class F>
void expectCleanError(F&& read)
{
    try
    {
        read();
    }
    catch (const std::bad_alloc& e)
    {
        std::fprintf(stderr, "quasiloc fuzz: std::bad_alloc (an allocation sized by the input): %s\n", e.what());
        std::abort();
    }
    catch (const std::length_error& e)
    {
        std::fprintf(stderr, "quasiloc fuzz: std::length_error (a length taken from the input): %s\n", e.what());
        std::abort();
    }
    catch (const std::exception& e)  // core::InputError, or what runProgram reports
    {
        // QUASILOC_FUZZ_VERBOSE=1 prints the errors (to check that a seed is accepted, or what an input hits).
        static const bool verbose = std::getenv("QUASILOC_FUZZ_VERBOSE") != nullptr;
        if (verbose) std::fprintf(stderr, "clean error: %s\n", e.what());
    }
}

inline std::vector<uint8_t> bytesOf(const uint8_t* data, size_t size)
{
    return std::vector<uint8_t>(data, data + size);
}

}  // namespace quasiloc::fuzz
