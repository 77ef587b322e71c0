// Reading stats.csv back (pbf plot, the poster frame of pbf run).
#include <fmt/format.h>

#include "pbf/io/csv_table.hpp"
#include "pbf/io/io.hpp"
#include "pbf/run/run.hpp"

namespace pbf {

const std::vector<double>& StatsTable::column(const std::string& name) const {
    for (std::size_t k = 0; k < names.size(); ++k)
        if (names[k] == name) return columns[k];
    throw IoError(file + ": no column '" + name + "' (a stats.csv of another pbf version?)");
}

StatsTable readStatsCsv(const std::filesystem::path& file) {
    if (!std::filesystem::exists(file))
        throw IoError(file.string() + ": cannot open (no stats.csv: is this a pbf run directory?)");
    CsvTable csv = readCsvTable(file);
    StatsTable table;
    table.file = std::move(csv.file);
    table.names = std::move(csv.names);
    table.columns = std::move(csv.columns);
    if (table.rows() == 0) throw IoError(table.file + ": no rows (the run wrote no frame)");
    return table;
}

int posterFrame(const StatsTable& stats, const std::function<bool(int frame)>& eligible) {
    const std::vector<double>& frames = stats.column("frame");
    const std::vector<double>& energy = stats.column("kinetic_energy");
    int best = -1;
    double bestEnergy = -1.0;
    for (std::size_t row = 0; row < stats.rows(); ++row) {
        const int frame = static_cast<int>(frames[row]);
        // Ties go to the earliest frame (a scene at rest: frame 0).
        if (!(energy[row] > bestEnergy) || !eligible(frame)) continue;
        best = frame;
        bestEnergy = energy[row];
    }
    return best;
}

}  // namespace pbf
