#pragma once
// A small strict JSON parser for the unit tests only (checks that what JsonWriter and the reports write is
// valid JSON and reads the values back). Throws std::runtime_error at the first syntax error.
#include <cctype>
#include <cstdlib>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace quasiloc::eval::testing
{
struct JsonValue
{
    enum class Type
    {
        Null,
        Bool,
        Number,
        String,
        Array,
        Object
    } type = Type::Null;
    bool boolean = false;
    double number = 0;
    std::string string;
    std::vector<JsonValue> array;
    std::map<std::string, JsonValue> object;

    const JsonValue& operator[](const std::string& key) const
    {
        const auto it = object.find(key);
        if (type != Type::Object || it == object.end()) throw std::runtime_error("no key '" + key + "'");
        return it->second;
    }
    const JsonValue& operator[](size_t i) const { return array.at(i); }
};

class JsonParser
{
   public:
    static JsonValue parse(const std::string& text)
    {
        JsonParser p(text);
        JsonValue v = p.value();
        p.ws();
        if (p.i_ != text.size()) p.fail("trailing characters");
        return v;
    }

   private:
    explicit JsonParser(const std::string& t) : s_(t) {}
    [[noreturn]] void fail(const std::string& what) const
    {
        throw std::runtime_error("JSON: " + what + " at offset " + std::to_string(i_));
    }
    void ws()
    {
        while (i_ < s_.size() && (s_[i_] == ' ' || s_[i_] == '\n' || s_[i_] == '\r' || s_[i_] == '\t')) ++i_;
    }
    void expect(char c)
    {
        ws();
        if (i_ >= s_.size() || s_[i_] != c) fail(std::string("expected '") + c + "'");
        ++i_;
    }
    bool literal(const char* word)
    {
        const std::string w(word);
        if (s_.compare(i_, w.size(), w) != 0) return false;
        i_ += w.size();
        return true;
    }
    JsonValue value()
    {
        ws();
        if (i_ >= s_.size()) fail("unexpected end");
        JsonValue v;
        const char c = s_[i_];
        if (c == '{') return object();
        if (c == '[') return array();
        if (c == '"')
        {
            v.type = JsonValue::Type::String;
            v.string = string();
        }
        else if (literal("null"))
            v.type = JsonValue::Type::Null;
        else if (literal("true"))
        {
            v.type = JsonValue::Type::Bool;
            v.boolean = true;
        }
        else if (literal("false"))
            v.type = JsonValue::Type::Bool;
        else
            v = numberValue();
        return v;
    }
    JsonValue numberValue()
    {
        const size_t start = i_;
        if (s_[i_] == '-') ++i_;
        if (i_ >= s_.size() || !std::isdigit(static_cast<unsigned char>(s_[i_]))) fail("bad value");
        if (s_[i_] == '0' && i_ + 1 < s_.size() && std::isdigit(static_cast<unsigned char>(s_[i_ + 1])))
            fail("leading zero");
        while (i_ < s_.size() && (std::isdigit(static_cast<unsigned char>(s_[i_])) || s_[i_] == '.' || s_[i_] == 'e' ||
                                  s_[i_] == 'E' || s_[i_] == '+' || s_[i_] == '-'))
            ++i_;
        const std::string tok = s_.substr(start, i_ - start);
        char* end = nullptr;
        JsonValue v;
        v.type = JsonValue::Type::Number;
        v.number = std::strtod(tok.c_str(), &end);
        if (end != tok.c_str() + tok.size()) fail("bad number '" + tok + "'");
        return v;
    }
    std::string string()
    {
        expect('"');
        std::string out;
        while (true)
        {
            if (i_ >= s_.size()) fail("unterminated string");
            const char c = s_[i_++];
            if (c == '"') return out;
            if (static_cast<unsigned char>(c) < 0x20) fail("raw control character in string");
            if (c != '\\')
            {
                out += c;
                continue;
            }
            if (i_ >= s_.size()) fail("bad escape");
            const char e = s_[i_++];
            switch (e)
            {
                case '"': out += '"'; break;
                case '\\': out += '\\'; break;
                case '/': out += '/'; break;
                case 'b': out += '\b'; break;
                case 'f': out += '\f'; break;
                case 'n': out += '\n'; break;
                case 'r': out += '\r'; break;
                case 't': out += '\t'; break;
                case 'u':
                {
                    if (i_ + 4 > s_.size()) fail("bad \\u escape");
                    const long code = std::strtol(s_.substr(i_, 4).c_str(), nullptr, 16);
                    if (code >= 0x80) fail("test parser handles ASCII \\u escapes only");
                    out += static_cast<char>(code);
                    i_ += 4;
                    break;
                }
                default: fail("bad escape");
            }
        }
    }
    JsonValue array()
    {
        expect('[');
        JsonValue v;
        v.type = JsonValue::Type::Array;
        ws();
        if (i_ < s_.size() && s_[i_] == ']') return ++i_, v;
        while (true)
        {
            v.array.push_back(value());
            ws();
            if (i_ < s_.size() && s_[i_] == ',')
            {
                ++i_;
                continue;
            }
            expect(']');
            return v;
        }
    }
    JsonValue object()
    {
        expect('{');
        JsonValue v;
        v.type = JsonValue::Type::Object;
        ws();
        if (i_ < s_.size() && s_[i_] == '}') return ++i_, v;
        while (true)
        {
            ws();
            const std::string k = string();
            if (v.object.count(k)) fail("duplicate key '" + k + "'");
            expect(':');
            v.object[k] = value();
            ws();
            if (i_ < s_.size() && s_[i_] == ',')
            {
                ++i_;
                continue;
            }
            expect('}');
            return v;
        }
    }
    const std::string& s_;
    size_t i_ = 0;
};

}  // namespace quasiloc::eval::testing
