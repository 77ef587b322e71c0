// VTK XML files for ParaView (and anything built on VTK): particle frames as
// unstructured grids (.vtu), triangle meshes as poly data (.vtp), and the
// .pvd collection that gives ParaView the simulated time of every file.
//
// Written by pbf's own small writer, not by Debian's VTK library
// (libvtk9-dev), for reasons measured on Debian 12 (docs/clients.md):
//  * libvtk9-dev depends on python3-vtk9, which python3-paraview conflicts
//    with: a machine with the VTK library cannot have pvpython, the tool that
//    tests these files the way a user opens them.
//  * libvtk9-dev installs 185 packages (565 MB, a JDK, MySQL, GDAL, HDF5,
//    Qt among them) for a format that is an XML header plus raw arrays.
//  * vtkXMLWriter writes to a file name, not a stream, so files would need a
//    second atomic-write path; through its output string a 1M-particle frame
//    took 5.4 s, this writer 0.25-0.38 s including fsync (as the PLY writer).
// The files follow VTK's XML format, version 1.0: little-endian raw arrays
// in one <AppendedData> block, each preceded by its UInt64 byte count.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "pbf/core/particles.hpp"
#include "pbf/core/vec3.hpp"

namespace pbf::vtk {

// Particles in id order as an UnstructuredGrid with one vertex cell per
// particle (ParaView's default Surface view draws vertex cells as points)
// and the point arrays velocity (Float32 x3), density (Float32) and id
// (UInt64); `time` (seconds) goes into the field array TimeValue, which
// ParaView reads when the .vtu files are opened as a series without the .pvd.
// Atomic (writeFileAtomically); throws IoError naming the file.
void writeParticlesVtu(const std::filesystem::path& path, const ParticleStore& particles,
                       double time);

// A triangle mesh as PolyData: Points, Polys and, when `normals` is not
// empty (one per vertex), the point array Normals. Atomic; throws IoError.
void writeTrianglesVtp(const std::filesystem::path& path, std::span<const Vec3> vertices,
                       std::span<const Vec3> normals,
                       std::span<const std::array<std::uint32_t, 3>> triangles, double time);

// One data set of a .pvd collection: `file` relative to the .pvd's folder.
struct CollectionEntry {
    double time = 0.0;  // seconds
    std::string file;
};

// Writes the whole collection (atomically), entries in the given order.
void writeCollection(const std::filesystem::path& path,
                     const std::vector<CollectionEntry>& entries);
// Adds one entry at the end of a collection written by writeCollection, in
// one write that replaces the closing tags (so a run that writes a frame at a
// time does not rewrite the whole list each frame): a killed run leaves the
// old or the new list. Throws IoError if the file does not end as
// writeCollection ends it.
void appendToCollection(const std::filesystem::path& path, const CollectionEntry& entry);

}  // namespace pbf::vtk
