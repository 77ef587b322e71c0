// Reading stats.csv back (pbf plot, the poster frame of pbf run).
#include <fmt/format.h>

#include <cerrno>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "pbf/run/run.hpp"

namespace pbf {
namespace {

std::vector<std::string> splitFields(const std::string& line) {
    std::vector<std::string> fields;
    std::stringstream in(line);
    std::string field;
    while (std::getline(in, field, ',')) fields.push_back(field);
    if (!line.empty() && line.back() == ',') fields.emplace_back();
    return fields;
}

}  // namespace

const std::vector<double>& StatsTable::column(const std::string& name) const {
    for (std::size_t k = 0; k < names.size(); ++k)
        if (names[k] == name) return columns[k];
    throw IoError(file + ": no column '" + name + "' (a stats.csv of another pbf version?)");
}

StatsTable readStatsCsv(const std::filesystem::path& file) {
    StatsTable table;
    table.file = file.string();
    std::ifstream in(file);
    if (!in)
        throw IoError(table.file + ": cannot open (no stats.csv: is this a pbf run directory?)");
    std::string line;
    if (!std::getline(in, line) || line.empty()) throw IoError(table.file + ": empty file");
    table.names = splitFields(line);
    table.columns.resize(table.names.size());
    int lineNumber = 1;
    while (std::getline(in, line)) {
        ++lineNumber;
        if (line.empty()) continue;
        const std::vector<std::string> fields = splitFields(line);
        if (fields.size() != table.names.size())
            throw IoError(fmt::format("{}:{}: {} values, the header has {} columns", table.file,
                                      lineNumber, fields.size(), table.names.size()));
        for (std::size_t k = 0; k < fields.size(); ++k) {
            const char* begin = fields[k].c_str();
            char* end = nullptr;
            errno = 0;
            const double value = std::strtod(begin, &end);
            if (end == begin || *end != '\0' || errno == ERANGE)
                throw IoError(fmt::format("{}:{}: {}: not a number: '{}'", table.file, lineNumber,
                                          table.names[k], fields[k]));
            table.columns[k].push_back(value);
        }
    }
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
