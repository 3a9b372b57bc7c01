#pragma once
// Strict readers of YAML files (EuRoC sensor.yaml, Kalibr camchain and IMU files) on yaml-cpp. Every problem is an
// InputError naming the file and the key. OpenCV's FileStorage is not used for user YAML: its parser hangs on some
// malformed files (docs/fuzzing.md).
#include <yaml-cpp/yaml.h>

#include <mrpt/poses/CPose3D.h>
#include <string>
#include <vector>

namespace quasiloc::core
{
/** The YAML document of `path`. OpenCV writes "%YAML:1.0" as the first line (EuRoC's sensor.yaml), which is not a
 *  valid YAML directive: that line is dropped. A file yaml-cpp cannot parse is InputError(path, "cannot parse as
 *  YAML: ..."). */
YAML::Node loadYamlFile(const std::string& path);

/** loadYamlFile, and the document must be a map of keys: `what` says which file was expected. */
YAML::Node loadYamlMap(const std::string& path, const std::string& what);

// yaml-cpp 0.7: a key that is absent gives a node on which only IsDefined() may be called (IsMap() etc. throw an
// unnamed InvalidNode), and a key looked up in a scalar throws BadSubscript. Callers check IsDefined() first and look
// keys up only in maps.

/** A finite number; `where` names the key in errors. */
double yamlNumber(const YAML::Node& node, const std::string& where);

/** A whole number in [min_value, max_value]. */
int yamlInteger(const YAML::Node& node, const std::string& where, int min_value, int max_value);

/** A list of finite numbers. */
std::vector<double> yamlNumbers(const YAML::Node& node, const std::string& where);

/** A scalar as text, or `default_value` when the key is absent. A map or list is an error. */
std::string yamlText(const YAML::Node& node, const std::string& where, const std::string& default_value);

/** A 4x4 row-major transform written as four rows of four numbers (Kalibr) or as an opencv-matrix with `data`
 *  (EuRoC's T_BS). */
mrpt::poses::CPose3D yamlTransform(const YAML::Node& node, const std::string& where);

}  // namespace quasiloc::core
