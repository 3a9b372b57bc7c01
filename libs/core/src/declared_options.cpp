#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <sstream>
#include <quasiloc/core/declared_options.h>
#include <quasiloc/core/error.h>
#include <quasiloc/core/ini_read.h>

namespace quasiloc::core
{
namespace
{
/** The shortest text that reads back as exactly `v` (0.05, not 0.050000000000000003; 3000, not 3e+03). */
std::string numberText(double v)
{
    char buf[40];
    if (v == std::floor(v) && std::abs(v) < 1e15)  // an integer as one: 20, not 2e+01
    {
        std::snprintf(buf, sizeof buf, "%.0f", v);
        return buf;
    }
    for (int precision = 1; precision <= 17; ++precision)
    {
        std::snprintf(buf, sizeof buf, "%.*g", precision, v);
        if (std::strtod(buf, nullptr) == v) break;
    }
    return buf;
}

/** The whole of `text` as an unsigned 64-bit integer (blanks after it allowed). */
bool parseUnsigned(const std::string& text, size_t& v)
{
    if (text.empty() || !std::isdigit(static_cast<unsigned char>(text[0]))) return false;
    char* end = nullptr;
    errno = 0;
    const unsigned long long u = std::strtoull(text.c_str(), &end, 10);
    while (*end == ' ' || *end == '\t') ++end;
    v = static_cast<size_t>(u);
    return errno == 0 && *end == '\0';
}

std::string joined(const std::vector<std::string>& names, const std::string& separator)
{
    std::string s;
    for (const auto& n : names) s += (s.empty() ? "" : separator) + n;
    return s;
}

bool sameIgnoringCase(const std::string& a, const std::string& b)
{
    return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](unsigned char x, unsigned char y) {
               return std::tolower(x) == std::tolower(y);
           });
}

/** "[a b, c]" -> {a, b, c}. */
std::vector<std::string> nameList(std::string text)
{
    for (char& ch : text)
        if (ch == '[' || ch == ']' || ch == ',' || ch == ';' || ch == '\t') ch = ' ';
    std::istringstream in(text);
    std::vector<std::string> names;
    for (std::string n; in >> n;) names.push_back(n);
    return names;
}
}  // namespace

bool Range::contains(double v) const
{
    const bool above_min = min_open ? v > min : v >= min;
    const bool below_max = max_open ? v < max : v <= max;
    return above_min && below_max;
}

std::string Range::text() const
{
    const bool has_min = std::isfinite(min), has_max = std::isfinite(max);
    if (!has_min && !has_max) return "any";
    if (!has_max) return (min_open ? "> " : ">= ") + numberText(min);
    if (!has_min) return (max_open ? "< " : "<= ") + numberText(max);
    return (min_open ? "(" : "[") + numberText(min) + ", " + numberText(max) + (max_open ? ")" : "]");
}

OptionTable::OptionTable(Action action, const mrpt::config::CConfigFileBase* in, mrpt::config::CConfigFileBase* out,
                         const std::string& section, const std::string& input)
    : action_(action), in_(in), out_(out), section_(section), input_(input)
{}

std::string OptionTable::where(const std::string& key) const
{
    // With a section: "<input>: [section] key", as check() functions name keys; without one the input names the
    // section already ("config.ini [World]"): "<input> key".
    if (section_.empty()) return input_.empty() ? key : input_ + " " + key;
    return (input_.empty() ? "" : input_ + ": ") + iniKeyName(section_, key);
}

std::string OptionTable::readText(const std::string& key) const { return in_->read_string(section_, key, "", false); }

void OptionTable::requireInRange(const std::string& key, double v, Range range) const
{
    require(range.contains(v), where(key), numberText(v) + " is out of range (must be " + range.text() + ")");
}

void OptionTable::emit(const std::string& key, const std::string& type, const std::string& unit,
                       const std::string& range, const std::string& value, const std::string& doc)
{
    // No comment after an empty value: MRPT would read "// comment" back as the value. No padding of the key: MRPT
    // would keep it in the key, and the same CConfigFileMemory could not read the value back.
    if (action_ == Action::Save)
        out_->write(section_, key, value, -1, 10, value.empty() ? "" : unit.empty() ? doc : "[" + unit + "] " + doc);
    if (action_ == Action::Describe) descriptions_.push_back({key, type, unit, range, value, doc});
}

void OptionTable::addNumber(const std::string& key, double current, bool integer, const std::string& unit, Range range,
                            const std::string& doc, const std::function<void(double)>& set)
{
    if (action_ == Action::Load)
    {
        const std::string text = readText(key);
        if (text.empty()) return;  // absent or empty: the default stays
        const std::string where = iniKeyName(section_, key);
        const double v = parseFiniteNumber(text, where);
        require(!integer || (v == std::floor(v) && std::abs(v) <= 1e9), where, "'" + text + "' is not an integer");
        require(range.contains(v), where, "'" + text + "' is out of range (must be " + range.text() + ")");
        set(v);
        return;
    }
    if (action_ == Action::Check) return requireInRange(key, current, range);
    emit(key, integer ? "integer" : "number", unit, range.text(), numberText(current), doc);
}

void OptionTable::add(const std::string& key, double& value, const std::string& unit, Range range,
                      const std::string& doc)
{
    addNumber(key, value, false, unit, range, doc, [&value](double v) { value = v; });
}

void OptionTable::add(const std::string& key, int& value, const std::string& unit, Range range, const std::string& doc)
{
    addNumber(key, value, true, unit, range, doc, [&value](double v) { value = int(v); });
}

void OptionTable::add(const std::string& key, size_t& value, const std::string& unit, Range range,
                      const std::string& doc)
{
    if (range.min < 0) range = Range{0, range.max, false, range.max_open};
    if (action_ == Action::Load)
    {
        const std::string text = readText(key);
        if (text.empty()) return;
        const std::string where = iniKeyName(section_, key);
        size_t v = 0;
        require(parseUnsigned(text, v), where, "'" + text + "' is not a non-negative integer");
        require(range.contains(double(v)), where, "'" + text + "' is out of range (must be " + range.text() + ")");
        value = v;
        return;
    }
    if (action_ == Action::Check) return requireInRange(key, double(value), range);
    emit(key, "integer", unit, range.text(), std::to_string(value), doc);
}

void OptionTable::add(const std::string& key, bool& value, const std::string& doc)
{
    if (action_ == Action::Load)
    {
        value = readIniBool(*in_, section_, key, value);
        return;
    }
    emit(key, "bool", "", "true, false", value ? "true" : "false", doc);
}

void OptionTable::add(const std::string& key, std::string& value, const std::string& doc)
{
    if (action_ == Action::Load)
    {
        value = in_->read_string(section_, key, value, false);
        return;
    }
    emit(key, "text", "", "", value, doc);
}

void OptionTable::add(const std::string& key, std::vector<double>& value, const std::string& unit, Range range,
                      const std::string& doc)
{
    if (action_ == Action::Load)
    {
        const std::vector<double> v = readIniVector(*in_, section_, key, value);
        for (double x : v)
            require(range.contains(x), iniKeyName(section_, key),
                    numberText(x) + " is out of range (each value must be " + range.text() + ")");
        value = v;
        return;
    }
    if (action_ == Action::Check)
    {
        for (double x : value) requireInRange(key, x, range);
        return;
    }
    std::vector<std::string> texts;
    for (double x : value) texts.push_back(numberText(x));
    emit(key, "numbers", unit, range.text(), "[" + joined(texts, " ") + "]", doc);
}

void OptionTable::add(const std::string& key, Eigen::Vector3d& value, const std::string& unit, Range range,
                      const std::string& doc)
{
    std::vector<double> v{value.x(), value.y(), value.z()};
    add(key, v, unit, range, doc);
    require(v.size() == 3, iniKeyName(section_, key),
            "expected 3 numbers like [0 0 0], got " + std::to_string(v.size()));
    value = Eigen::Vector3d(v[0], v[1], v[2]);
}

void OptionTable::add(const std::string& key, std::vector<std::string>& value, const std::string& doc)
{
    if (action_ == Action::Load)
    {
        const std::string text = readText(key);
        if (!text.empty()) value = nameList(text);  // absent or empty: the default stays
        return;
    }
    emit(key, "names", "", "", "[" + joined(value, " ") + "]", doc);
}

void OptionTable::addChoice(const std::string& key, const std::vector<std::string>& names, int current,
                            const std::function<void(size_t)>& set, const std::string& doc)
{
    if (action_ == Action::Load)
    {
        const std::string text = readText(key);
        if (text.empty()) return;
        for (size_t i = 0; i < names.size(); ++i)
            if (sameIgnoringCase(names[i], text)) return set(i);
        throw InputError(iniKeyName(section_, key), "'" + text + "' is not one of " + joined(names, ", "));
    }
    if (action_ == Action::Check)
        return require(current >= 0, where(key), "the present value is not one of " + joined(names, ", "));
    require(current >= 0, iniKeyName(section_, key), "the present value has no name (declaration incomplete)");
    emit(key, "one of", "", joined(names, ", "), names[size_t(current)], doc);
}

void DeclaredOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg, const std::string& section)
{
    OptionTable t(OptionTable::Action::Load, &cfg, nullptr, section);
    declare(t);
}

void DeclaredOptions::saveToConfigFile(mrpt::config::CConfigFileBase& cfg, const std::string& section) const
{
    OptionTable t(OptionTable::Action::Save, nullptr, &cfg, section);
    // declare() takes the members by reference for loading; saving only reads them.
    const_cast<DeclaredOptions*>(this)->declare(t);
}

std::vector<OptionDescription> DeclaredOptions::describe() const
{
    OptionTable t(OptionTable::Action::Describe, nullptr, nullptr, "");
    const_cast<DeclaredOptions*>(this)->declare(t);
    return t.descriptions();
}

void DeclaredOptions::checkRanges(const std::string& input, const std::string& section) const
{
    OptionTable t(OptionTable::Action::Check, nullptr, nullptr, section, input);
    const_cast<DeclaredOptions*>(this)->declare(t);
}

}  // namespace quasiloc::core
