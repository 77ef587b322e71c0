// A CSV file of numbers with a header line (pbf's stats.csv, a motion's
// keyframes): every column by name, one value per row.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace pbf {

struct CsvTable {
    std::string file;  // for messages
    std::vector<std::string> names;
    std::vector<std::vector<double>> columns;  // columns[k] holds the values of names[k]
    std::size_t rows() const { return columns.empty() ? 0 : columns.front().size(); }
    // The column called `name`, or null.
    const std::vector<double>* find(const std::string& name) const;
};

// Throws IoError naming the file (and the line and column) when it cannot be
// opened, is empty, or has a row that is not as many numbers as the header
// has names. Blank lines are skipped; names are trimmed of spaces.
CsvTable readCsvTable(const std::filesystem::path& file);

}  // namespace pbf
