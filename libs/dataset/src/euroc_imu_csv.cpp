#include <cstdio>
#include <quasiloc/core/error.h>
#include <quasiloc/core/ini_read.h>
#include <quasiloc/dataset/euroc_imu_csv.h>
#include <quasiloc/dataset/timestamps.h>

#include "euroc_csv.h"

namespace quasiloc::dataset
{
namespace
{
/** Reads the data rows of a csv with `columns` fields whose first is t_ns; checks the time order and the gap
 *  bound; calls row(t_ns, values of columns 1.., where) for each. */
template <typename RowFn>
void readTimedRows(const std::string& path, size_t columns, const std::string& layout, double nominal_rate_hz,
                   RowFn&& row)
{
    core::require(nominal_rate_hz > 0, path, "nominal IMU rate must be > 0 Hz");
    const double max_gap_ns = kMaxImuGapPeriods * 1e9 / nominal_rate_hz;
    const auto lines = csv::readLines(path);
    core::require(!lines.empty(), path, "holds no data row");
    std::int64_t prev_t = -1;
    std::vector<double> values(columns - 1);
    for (const auto& l : lines)
    {
        const std::string where = csv::where(path, l);
        core::require(l.fields.size() == columns, where,
                      "expected " + std::to_string(columns) + " columns '" + layout + "', got " +
                          std::to_string(l.fields.size()));
        const std::int64_t t = csv::parseTimestampNs(l.fields[0], where);
        if (prev_t >= 0)
        {
            core::require(t != prev_t, where,
                          "duplicated timestamp " + std::to_string(t) + " (same as the previous row)");
            core::require(t > prev_t, where,
                          "timestamps not increasing: " + std::to_string(t) + " is " + std::to_string(prev_t - t) +
                              " ns before the previous row's");
            if (static_cast<double>(t - prev_t) > max_gap_ns)
            {
                char msg[160];
                std::snprintf(msg, sizeof(msg),
                              "gap of %.3f ms before this row (the bound is %.1f periods = %.3f ms at %g Hz)",
                              (t - prev_t) * 1e-6, kMaxImuGapPeriods, max_gap_ns * 1e-6, nominal_rate_hz);
                throw core::InputError(where, msg);
            }
        }
        for (size_t i = 1; i < columns; ++i) values[i - 1] = core::parseFiniteNumber(l.fields[i], where);
        row(t, values);
        prev_t = t;
    }
}
}  // namespace

EurocImuCsv readEurocImuCsv(const std::string& path, double nominal_rate_hz)
{
    EurocImuCsv out;
    out.path = path;
    readTimedRows(path, 7, "t_ns, w_x, w_y, w_z, a_x, a_y, a_z", nominal_rate_hz,
                  [&](std::int64_t t, const std::vector<double>& v) {
                      ImuSample s;
                      s.t = nsToSeconds(t);
                      s.gyro = {v[0], v[1], v[2]};  // EuRoC puts the angular rate first
                      s.acc = {v[3], v[4], v[5]};
                      out.t_ns.push_back(t);
                      out.samples.push_back(s);
                  });
    return out;
}

EurocBiasCsv readEurocBiasCsv(const std::string& path, double nominal_rate_hz)
{
    EurocBiasCsv out;
    out.path = path;
    readTimedRows(path, 17, "t_ns, p xyz, q wxyz, v xyz, b_w xyz, b_a xyz", nominal_rate_hz,
                  [&](std::int64_t t, const std::vector<double>& v) {
                      out.t_ns.push_back(t);
                      out.gyro_bias.emplace_back(v[10], v[11], v[12]);
                      out.acc_bias.emplace_back(v[13], v[14], v[15]);
                  });
    return out;
}

}  // namespace quasiloc::dataset
