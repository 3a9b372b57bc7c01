#include <cmath>
#include <fstream>
#include <quasiloc/core/error.h>
#include <quasiloc/core/pose.h>
#include <quasiloc/core/yaml_read.h>
#include <sstream>

namespace quasiloc::core
{
YAML::Node loadYamlFile(const std::string& path)
{
    std::ifstream f(path, std::ios::binary);
    require(f.good(), path, "cannot open the YAML file");
    std::stringstream text;
    text << f.rdbuf();
    std::string s = text.str();
    if (s.rfind("%YAML:", 0) == 0)
    {
        const size_t eol = s.find('\n');
        s = eol == std::string::npos ? std::string() : s.substr(eol);
    }
    try
    {
        return YAML::Load(s);
    }
    catch (const YAML::Exception& e)
    {
        throw InputError(path, std::string("cannot parse as YAML: ") + e.what());
    }
}

YAML::Node loadYamlMap(const std::string& path, const std::string& what)
{
    const YAML::Node doc = loadYamlFile(path);
    require(doc.IsMap(), path, "cannot parse as YAML " + what + ": the document is not a map of keys");
    return doc;
}

double yamlNumber(const YAML::Node& node, const std::string& where)
{
    require(node.IsDefined() && node.IsScalar(), where, "missing or not a number");
    try
    {
        const double v = node.as<double>();
        require(std::isfinite(v), where, "is not finite");
        return v;
    }
    catch (const YAML::Exception&)
    {
        throw InputError(where, "not a number ('" + node.Scalar() + "')");
    }
}

int yamlInteger(const YAML::Node& node, const std::string& where, int min_value, int max_value)
{
    const double v = yamlNumber(node, where);
    require(v == std::floor(v) && v >= min_value && v <= max_value, where,
            "must be a whole number in [" + std::to_string(min_value) + ", " + std::to_string(max_value) + "], got '" +
                node.Scalar() + "'");
    return int(v);
}

std::vector<double> yamlNumbers(const YAML::Node& node, const std::string& where)
{
    require(node.IsDefined() && node.IsSequence(), where, "missing or not a list of numbers");
    std::vector<double> v;
    for (size_t i = 0; i < node.size(); ++i) v.push_back(yamlNumber(node[i], where + "[" + std::to_string(i) + "]"));
    return v;
}

std::string yamlText(const YAML::Node& node, const std::string& where, const std::string& default_value)
{
    if (!node.IsDefined() || node.IsNull()) return default_value;
    require(node.IsScalar(), where, "must be a single value, not a list or map");
    return node.Scalar();
}

mrpt::poses::CPose3D yamlTransform(const YAML::Node& node, const std::string& where)
{
    require(node.IsDefined(), where, "missing (a 4x4 transform expected)");
    std::vector<double> values;
    if (node.IsMap())
        values = yamlNumbers(node["data"], where + ".data");
    else
    {
        require(node.IsSequence() && node.size() == 4, where, "must be 4 rows of 4 numbers");
        for (size_t r = 0; r < 4; ++r)
        {
            const auto row = yamlNumbers(node[r], where + " row " + std::to_string(r));
            require(row.size() == 4, where, "row " + std::to_string(r) + " must hold 4 numbers");
            values.insert(values.end(), row.begin(), row.end());
        }
    }
    require(values.size() == 16, where, "must hold 16 values (4x4 row-major)");
    return fromMatrixRowMajor(values, where);
}

}  // namespace quasiloc::core
