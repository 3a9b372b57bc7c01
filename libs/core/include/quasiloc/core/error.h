#pragma once
// Errors raised by quasiloc libraries. A message always names the input (file, INI key, argument)
// and what is wrong with it; libraries throw, programs catch in main() and exit non-zero.
#include <stdexcept>
#include <string>

namespace quasiloc::core
{
/** Bad user input: a missing or malformed file, an invalid option value, an unknown INI key. */
class InputError : public std::runtime_error
{
   public:
    InputError(const std::string& input, const std::string& problem)
        : std::runtime_error(input + ": " + problem), input_(input), problem_(problem)
    {}
    const std::string& input() const { return input_; }
    const std::string& problem() const { return problem_; }

   private:
    std::string input_, problem_;
};

/** Throws InputError(input, problem) when `condition` is false. */
inline void require(bool condition, const std::string& input, const std::string& problem)
{
    if (!condition) throw InputError(input, problem);
}

}  // namespace quasiloc::core
