#include <cmath>
#include <fstream>
#include <quasiloc/core/error.h>
#include <quasiloc/sim/euroc_room_data.h>
#include <sstream>

namespace quasiloc::sim
{
std::vector<LineSegment3D> readLineSegments(const std::string& path)
{
    std::ifstream f(path);
    core::require(f.good(), path, "cannot open line map");
    std::vector<LineSegment3D> lines;
    std::string line;
    for (int row = 1; std::getline(f, line); ++row)
    {
        if (line.find_first_not_of(" \t\r") == std::string::npos || line[0] == '#') continue;
        std::istringstream ss(line);
        double v[6];
        std::string extra;
        for (double& x : v)
            core::require(static_cast<bool>(ss >> x) && std::isfinite(x), path + ":" + std::to_string(row),
                          "expected 6 finite numbers x1 y1 z1 x2 y2 z2");
        core::require(!(ss >> extra), path + ":" + std::to_string(row), "more than 6 values");
        lines.push_back({{v[0], v[1], v[2]}, {v[3], v[4], v[5]}});
    }
    core::require(!lines.empty(), path, "no line segments");
    return lines;
}

}  // namespace quasiloc::sim
