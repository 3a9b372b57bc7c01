#pragma once
// Options declared once. An options struct lists each of its keys in one place, declare(OptionTable&): the key's
// name, the member it fills, its unit, its valid range and one line of documentation. Loading (strict: a value out
// of range or not of the key's type is an InputError naming the key), saving, the known-key list that rejects
// unknown keys (program_options.h: loadOptionsChecked) and the generated reference docs/options.md all come from
// that declaration, and so does checkRanges(), which tests values set in code (not loaded) against the declared
// ranges. Checks that relate two keys stay in the struct's own check().
//
//     struct FooOptions : core::DeclaredOptions {
//         double max_depth_m = 6;
//         Mode mode = Mode::Fast;
//         void declare(core::OptionTable& t) override {
//             t.add("max_depth_m", max_depth_m, "m", core::Range::above(0), "points farther away are dropped");
//             t.addEnum("mode", mode, {{"fast", Mode::Fast}, {"full", Mode::Full}}, "the search budget");
//         }
//     };
#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/config/CLoadableOptions.h>

#include <Eigen/Core>
#include <functional>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace quasiloc::core
{
/** The valid values of a number: [min, max], either end open or unbounded. */
struct Range
{
    double min = -std::numeric_limits<double>::infinity();
    double max = std::numeric_limits<double>::infinity();
    bool min_open = false, max_open = false;

    static Range any() { return {}; }
    static Range atLeast(double lo) { return {lo, std::numeric_limits<double>::infinity(), false, false}; }
    static Range above(double lo) { return {lo, std::numeric_limits<double>::infinity(), true, false}; }
    static Range between(double lo, double hi) { return {lo, hi, false, false}; }
    /** [lo, hi) */
    static Range fromUpTo(double lo, double hi) { return {lo, hi, false, true}; }
    /** (lo, hi) */
    static Range strictlyBetween(double lo, double hi) { return {lo, hi, true, true}; }

    bool contains(double v) const;
    /** "> 0", ">= 1", "[0, 1)", "any", ...: how errors and the reference state it. */
    std::string text() const;
};

/** One declared key, as the reference lists it. */
struct OptionDescription
{
    std::string key, type, unit, range, default_value, doc;
};

/** The declarations of one options struct, and what is done with them (load, save or describe). */
class OptionTable
{
   public:
    void add(const std::string& key, double& value, const std::string& unit, Range range, const std::string& doc);
    void add(const std::string& key, int& value, const std::string& unit, Range range, const std::string& doc);
    /** Read exactly, all 64 bits (seeds); the range is compared as a double. */
    void add(const std::string& key, size_t& value, const std::string& unit, Range range, const std::string& doc);
    void add(const std::string& key, bool& value, const std::string& doc);
    /** Free text: a path, a name. */
    void add(const std::string& key, std::string& value, const std::string& doc);
    /** "[a b c]" of numbers, each in `range`. */
    void add(const std::string& key, std::vector<double>& value, const std::string& unit, Range range,
             const std::string& doc);
    /** "[x y z]": exactly three numbers, each in `range`. */
    void add(const std::string& key, Eigen::Vector3d& value, const std::string& unit, Range range,
             const std::string& doc);
    /** "[a b c]" of names (blanks or commas between them, brackets optional). */
    void add(const std::string& key, std::vector<std::string>& value, const std::string& doc);
    /** One of the named values (matched without regard to case: "SE3" is "se3"); an other name is an InputError
     *  listing them. A value may have several names (an alias kept so that old INI files stay valid): the first one
     *  is the name saved. */
    template <class E>
    void addEnum(const std::string& key, E& value, const std::vector<std::pair<std::string, E>>& names,
                 const std::string& doc)
    {
        std::vector<std::string> texts;
        int current = -1;
        for (size_t i = 0; i < names.size(); ++i)
        {
            texts.push_back(names[i].first);
            if (current < 0 && names[i].second == value) current = int(i);
        }
        addChoice(
            key, texts, current, [&value, names](size_t i) { value = names[i].second; }, doc);
    }

    enum class Action
    {
        Load,
        Save,
        Describe,
        Check  ///< the present values against the declared ranges; errors name `input` and the key
    };
    OptionTable(Action action, const mrpt::config::CConfigFileBase* in, mrpt::config::CConfigFileBase* out,
                const std::string& section, const std::string& input = "");
    const std::vector<OptionDescription>& descriptions() const { return descriptions_; }

   private:
    void addChoice(const std::string& key, const std::vector<std::string>& names, int current,
                   const std::function<void(size_t)>& set, const std::string& doc);
    void addNumber(const std::string& key, double current, bool integer, const std::string& unit, Range range,
                   const std::string& doc, const std::function<void(double)>& set);
    void requireInRange(const std::string& key, double v, Range range) const;
    void emit(const std::string& key, const std::string& type, const std::string& unit, const std::string& range,
              const std::string& value, const std::string& doc);
    std::string readText(const std::string& key) const;
    /** "[section] key", after "<input>: " when checking. */
    std::string where(const std::string& key) const;

    Action action_;
    const mrpt::config::CConfigFileBase* in_;
    mrpt::config::CConfigFileBase* out_;
    std::string section_, input_;
    std::vector<OptionDescription> descriptions_;
};

/** An options struct whose keys are declared once (declare()); load and save follow from it. */
struct DeclaredOptions : public mrpt::config::CLoadableOptions
{
    /** Every key of the struct, in the order the effective configuration and the reference list them. */
    virtual void declare(OptionTable& table) = 0;

    void loadFromConfigFile(const mrpt::config::CConfigFileBase& cfg, const std::string& section) override;
    void saveToConfigFile(mrpt::config::CConfigFileBase& cfg, const std::string& section) const override;
    /** The declared keys with their defaults (the struct's present values), for the reference. */
    std::vector<OptionDescription> describe() const;
    /** InputError "<input>: [section] key: ..." for a present value outside its declared range (options set in
     *  code rather than loaded, e.g. before a library uses them). */
    void checkRanges(const std::string& input, const std::string& section = "") const;
};

}  // namespace quasiloc::core
