// rgvc_sweep's results: the Pareto front per scene, the best settings, the CSV and the printed tables.
#pragma once

#include "SweepRunner.hpp"

#include <ostream>
#include <string>
#include <vector>

namespace rgvc::bench {

/// [ms] the time a setting is judged by: its frame time with drawing when drawn, else its cull time.
double judgedMs(const SweepRow& r);

/// Marks SweepRow::pareto: per scene, among the conservative settings with 0 misses and a ratio, those
/// no other such setting beats on both judgedMs and ratio (and ties on neither).
void markPareto(std::vector<SweepRow>& rows);

struct SweepBest {
    const SweepRow* fastest = nullptr; ///< the fastest setting on the front
    const SweepRow* tightest = nullptr; ///< the front's lowest ratio within 1.5x the fastest's time
};
/// The best settings of `scene` (after markPareto); null members when no setting qualifies.
SweepBest bestOf(const std::vector<SweepRow>& rows, const std::string& scene);

/// The CSV: `#` header lines (each of `header` prefixed by "# "), a column line, one row per setting.
void writeCsv(std::ostream& out, const std::vector<std::string>& header, const std::vector<SweepRow>& rows);

/// The per-setting table of one scene and the best-setting table of all scenes, as markdown.
void printSceneTable(const std::vector<SweepRow>& rows, const std::string& scene);
void printBestTable(const std::vector<SweepRow>& rows, const std::vector<std::string>& scenes);

} // namespace rgvc::bench
