#include "pbf/io/motion_file.hpp"

#include <fmt/format.h>

#include "pbf/core/errors.hpp"
#include "pbf/io/csv_table.hpp"
#include "pbf/io/io.hpp"

namespace pbf {

std::vector<MotionKey> readMotionCsv(const std::string& path, const std::string& field) {
    CsvTable table;
    try {
        table = readCsvTable(path);
    } catch (const IoError& e) {
        throw SceneError(field + ".file: " + e.what());
    }
    const auto column = [&](const char* name, bool required) {
        const std::vector<double>* c = table.find(name);
        if (!c && required)
            throw SceneError(fmt::format(
                "{}: {}: no column '{}' (the header needs time, x, y, z; rx, ry, rz are optional "
                "rotations in degrees)",
                field, path, name));
        return c;
    };
    const auto* time = column("time", true);
    const auto *x = column("x", true), *y = column("y", true), *z = column("z", true);
    const auto *rx = column("rx", false), *ry = column("ry", false), *rz = column("rz", false);
    std::vector<MotionKey> keys(table.rows());
    for (std::size_t k = 0; k < keys.size(); ++k) {
        keys[k].time = (*time)[k];
        keys[k].position = {float((*x)[k]), float((*y)[k]), float((*z)[k])};
        keys[k].rotationDegrees = {rx ? float((*rx)[k]) : 0.0f, ry ? float((*ry)[k]) : 0.0f,
                                   rz ? float((*rz)[k]) : 0.0f};
    }
    return keys;
}

}  // namespace pbf
