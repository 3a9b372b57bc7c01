#pragma once
// A minimal streaming JSON writer (no third-party dependency): objects, arrays, strings with RFC 8259
// escaping, numbers (non-finite -> null), booleans. Commas and indentation are handled here; misuse
// (a value without a key inside an object, unbalanced end) throws std::logic_error.
#include <string>
#include <vector>

namespace quasiloc::eval
{
class JsonWriter
{
   public:
    explicit JsonWriter(int indent = 2) : indent_(indent) {}

    JsonWriter& beginObject();
    JsonWriter& endObject();
    JsonWriter& beginArray();
    JsonWriter& endArray();
    /** Inside an object: the key of the next value. */
    JsonWriter& key(const std::string& k);

    JsonWriter& value(const std::string& s);
    JsonWriter& value(const char* s) { return value(std::string(s)); }
    JsonWriter& value(double v);  ///< shortest of 15-17 significant digits that round-trips; NaN/inf -> null
    JsonWriter& value(int v) { return value(static_cast<long long>(v)); }
    JsonWriter& value(long long v);
    JsonWriter& value(unsigned long v) { return value(static_cast<long long>(v)); }
    JsonWriter& value(unsigned long long v) { return value(static_cast<long long>(v)); }
    JsonWriter& value(bool b);
    JsonWriter& null();

    /** The document; throws std::logic_error if an object or array is still open. */
    std::string str() const;

    static std::string escape(const std::string& s);  ///< quoted and escaped

   private:
    struct Level
    {
        bool is_object;
        bool empty = true;
        bool key_pending = false;
    };
    void beforeValue();
    void newline();
    std::string out_;
    std::vector<Level> stack_;
    int indent_;
    bool root_written_ = false;
};

}  // namespace quasiloc::eval
