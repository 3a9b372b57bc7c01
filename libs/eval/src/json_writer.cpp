#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <quasiloc/eval/json_writer.h>
#include <stdexcept>

namespace quasiloc::eval
{
std::string JsonWriter::escape(const std::string& s)
{
    std::string o = "\"";
    for (const char ch : s)
    {
        const auto c = static_cast<unsigned char>(ch);
        switch (c)
        {
            case '"': o += "\\\""; break;
            case '\\': o += "\\\\"; break;
            case '\b': o += "\\b"; break;
            case '\f': o += "\\f"; break;
            case '\n': o += "\\n"; break;
            case '\r': o += "\\r"; break;
            case '\t': o += "\\t"; break;
            default:
                if (c < 0x20)
                {
                    char buf[8];
                    std::snprintf(buf, sizeof(buf), "\\u%04x", c);
                    o += buf;
                }
                else
                    o += ch;  // UTF-8 bytes pass through unchanged
        }
    }
    return o + "\"";
}

void JsonWriter::newline()
{
    if (indent_ <= 0) return;
    out_ += '\n';
    out_.append(stack_.size() * static_cast<size_t>(indent_), ' ');
}

void JsonWriter::beforeValue()
{
    if (stack_.empty())
    {
        if (root_written_) throw std::logic_error("JsonWriter: a second top-level value");
        root_written_ = true;
        return;
    }
    Level& l = stack_.back();
    if (l.is_object)
    {
        if (!l.key_pending) throw std::logic_error("JsonWriter: value in an object without a key");
        l.key_pending = false;
        return;
    }
    if (!l.empty) out_ += ',';
    l.empty = false;
    newline();
}

JsonWriter& JsonWriter::key(const std::string& k)
{
    if (stack_.empty() || !stack_.back().is_object || stack_.back().key_pending)
        throw std::logic_error("JsonWriter: key '" + k + "' outside an object or after another key");
    Level& l = stack_.back();
    if (!l.empty) out_ += ',';
    l.empty = false;
    l.key_pending = true;
    newline();
    out_ += escape(k);
    out_ += indent_ > 0 ? ": " : ":";
    return *this;
}

JsonWriter& JsonWriter::beginObject()
{
    beforeValue();
    out_ += '{';
    stack_.push_back({true});
    return *this;
}

JsonWriter& JsonWriter::beginArray()
{
    beforeValue();
    out_ += '[';
    stack_.push_back({false});
    return *this;
}

JsonWriter& JsonWriter::endObject()
{
    if (stack_.empty() || !stack_.back().is_object || stack_.back().key_pending)
        throw std::logic_error("JsonWriter: endObject without a matching open object (or after a key)");
    const bool empty = stack_.back().empty;
    stack_.pop_back();
    if (!empty) newline();
    out_ += '}';
    return *this;
}

JsonWriter& JsonWriter::endArray()
{
    if (stack_.empty() || stack_.back().is_object)
        throw std::logic_error("JsonWriter: endArray without a matching open array");
    const bool empty = stack_.back().empty;
    stack_.pop_back();
    if (!empty) newline();
    out_ += ']';
    return *this;
}

JsonWriter& JsonWriter::value(const std::string& s)
{
    beforeValue();
    out_ += escape(s);
    return *this;
}

JsonWriter& JsonWriter::value(double v)
{
    if (!std::isfinite(v)) return null();
    beforeValue();
    // Shortest of 15..17 significant digits that reads back to the same double.
    char buf[32];
    for (int digits = 15; digits <= 17; ++digits)
    {
        std::snprintf(buf, sizeof(buf), "%.*g", digits, v);
        if (std::strtod(buf, nullptr) == v) break;
    }
    out_ += buf;
    return *this;
}

JsonWriter& JsonWriter::value(long long v)
{
    beforeValue();
    out_ += std::to_string(v);
    return *this;
}

JsonWriter& JsonWriter::value(bool b)
{
    beforeValue();
    out_ += b ? "true" : "false";
    return *this;
}

JsonWriter& JsonWriter::null()
{
    beforeValue();
    out_ += "null";
    return *this;
}

std::string JsonWriter::str() const
{
    if (!stack_.empty()) throw std::logic_error("JsonWriter: unclosed object or array");
    return out_ + "\n";
}

}  // namespace quasiloc::eval
