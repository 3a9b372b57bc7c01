#pragma once
// Internal helpers shared by the cloud readers.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace quasiloc::map::detail
{
/** The whole file. InputError naming `path` if it is missing, not a regular file or unreadable. */
std::vector<uint8_t> readFileBytes(const std::string& path);

/** Lower-case copy. */
std::string lowerCase(std::string s);

/** Splits on blanks (spaces, tabs, \r). */
std::vector<std::string> splitWords(std::string_view line);

/** Parses a whole token as a number (also "nan", "inf"); false if the token is not a number. */
bool parseNumber(std::string_view token, double& value);

/** A cursor over whitespace-separated tokens of an ASCII data section. */
class TokenCursor
{
   public:
    TokenCursor(const uint8_t* begin, const uint8_t* end) : p_(begin), end_(end) {}
    /** Next token; false at the end of the data. */
    bool next(std::string_view& token);
    /** Next token parsed as a number; InputError naming `path` and "<element> #<index>" on a missing or
     *  bad value (the message is only built on failure: this runs once per value). */
    double number(const std::string& path, const char* element, size_t index);

   private:
    const uint8_t* p_;
    const uint8_t* end_;
};

}  // namespace quasiloc::map::detail
