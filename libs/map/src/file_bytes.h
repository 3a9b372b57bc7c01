#pragma once
// Internal helpers shared by the cloud readers.
#include <cmath>
#include <cstdint>
#include <quasiloc/map/map_import.h>
#include <string>
#include <string_view>
#include <vector>

namespace quasiloc::map::detail
{
/** The whole file. InputError naming `path` if it is missing, not a regular file or unreadable. */
std::vector<uint8_t> readFileBytes(const std::string& path);

/** The readers' parsers over the bytes of a file; `path` names them in errors (readCloudBytes dispatches). */
RawCloud parsePly(const std::vector<uint8_t>& bytes, const std::string& path);
RawCloud parsePcd(const std::vector<uint8_t>& bytes, const std::string& path);
RawCloud parseKittiBin(const std::vector<uint8_t>& bytes, const std::string& path);
RawCloud parseXyziText(const std::vector<uint8_t>& bytes, const std::string& path);

/** a * b, false when it overflows size_t (counts and sizes read from a file are multiplied through this). */
inline bool multiply(size_t a, size_t b, size_t& product) { return !__builtin_mul_overflow(a, b, &product); }

/** A count read from a file: a whole number in [0, max]; false otherwise (also for NaN, inf, 1e300, which must not
 *  reach a cast to size_t: that is undefined behaviour). */
inline bool countInRange(double v, size_t max, size_t& count)
{
    constexpr double kMaxExact = 9007199254740992.0;  // 2^53: every whole number up to here is exact
    if (!(v >= 0 && v <= kMaxExact && v == std::floor(v))) return false;
    count = static_cast<size_t>(v);
    return count <= max;
}

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
