#include "pbf/io/csv_table.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "pbf/io/io.hpp"

namespace pbf {
namespace {

std::string trimmed(const std::string& s) {
    const auto begin = s.find_first_not_of(" \t\r");
    if (begin == std::string::npos) return {};
    return s.substr(begin, s.find_last_not_of(" \t\r") - begin + 1);
}

std::vector<std::string> splitFields(const std::string& line) {
    std::vector<std::string> fields;
    std::stringstream in(line);
    std::string field;
    while (std::getline(in, field, ',')) fields.push_back(trimmed(field));
    if (!line.empty() && line.back() == ',') fields.emplace_back();
    return fields;
}

}  // namespace

const std::vector<double>* CsvTable::find(const std::string& name) const {
    for (std::size_t k = 0; k < names.size(); ++k)
        if (names[k] == name) return &columns[k];
    return nullptr;
}

CsvTable readCsvTable(const std::filesystem::path& file) {
    CsvTable table;
    table.file = file.string();
    std::ifstream in(file);
    if (!in) throw IoError(table.file + ": cannot open");
    std::string line;
    if (!std::getline(in, line) || trimmed(line).empty())
        throw IoError(table.file + ": empty file");
    table.names = splitFields(line);
    table.columns.resize(table.names.size());
    int lineNumber = 1;
    while (std::getline(in, line)) {
        ++lineNumber;
        if (trimmed(line).empty()) continue;
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
    return table;
}

}  // namespace pbf
