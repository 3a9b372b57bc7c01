#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <quasiloc/eval/json_writer.h>

#include "json_test_parser.h"

using quasiloc::eval::JsonWriter;
using quasiloc::eval::testing::JsonParser;
using quasiloc::eval::testing::JsonValue;

TEST(JsonWriter, ExactCompactTextWithEscaping)
{
    JsonWriter j(0);
    j.beginObject();
    j.key("s").value(std::string("q\"b\\n\nt\t\x01 é"));
    j.key("a").beginArray().value(1).value(2.5).value(std::numeric_limits<double>::quiet_NaN()).value(true).endArray();
    j.key("e").beginObject().endObject();
    j.key("k\"ey").value(0.1);
    j.endObject();
    EXPECT_EQ(j.str(), "{\"s\":\"q\\\"b\\\\n\\nt\\t\\u0001 é\",\"a\":[1,2.5,null,true],\"e\":{},\"k\\\"ey\":0.1}\n");
}

TEST(JsonWriter, IndentedOutputParsesBack)
{
    JsonWriter j;
    j.beginObject();
    j.key("name").value("a \"quoted\"\\path\r\n");
    j.key("pi").value(M_PI);
    j.key("big").value(1.0e300);
    j.key("neg").value(-1234567890123LL);
    j.key("list").beginArray();
    j.beginObject().key("x").value(false).endObject();
    j.beginArray().endArray();
    j.null();
    j.endArray();
    j.endObject();
    const JsonValue v = JsonParser::parse(j.str());
    EXPECT_EQ(v["name"].string, "a \"quoted\"\\path\r\n");
    EXPECT_EQ(v["pi"].number, M_PI);  // round-trips exactly
    EXPECT_EQ(v["big"].number, 1.0e300);
    EXPECT_EQ(v["neg"].number, -1234567890123.0);
    ASSERT_EQ(v["list"].array.size(), 3u);
    EXPECT_EQ(v["list"][0]["x"].type, JsonValue::Type::Bool);
    EXPECT_FALSE(v["list"][0]["x"].boolean);
    EXPECT_TRUE(v["list"][1].array.empty());
    EXPECT_EQ(v["list"][2].type, JsonValue::Type::Null);
}

TEST(JsonWriter, MisuseThrows)
{
    JsonWriter a;
    a.beginObject();
    EXPECT_THROW(a.value(1), std::logic_error);  // value without a key
    EXPECT_THROW(a.str(), std::logic_error);     // still open
    JsonWriter b;
    b.beginArray();
    EXPECT_THROW(b.key("k"), std::logic_error);
    EXPECT_THROW(b.endObject(), std::logic_error);
    JsonWriter c;
    c.value(1);
    EXPECT_THROW(c.value(2), std::logic_error);  // second root
}

TEST(JsonTestParser, RejectsInvalidJson)
{
    for (const char* bad : {"{", "[1,]", "{\"a\" 1}", "01", "\"x", "{\"a\":1,\"a\":2}", "[1] x", "nul"})
        EXPECT_THROW(JsonParser::parse(bad), std::runtime_error) << bad;
}
