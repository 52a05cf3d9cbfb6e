#pragma once
// Output paths given on the command line: their folders are created before any long work
// starts, so a typo fails in a second instead of after a bake, and an existing file is only
// replaced when lightbake wrote it (or the user says --force).

#include <string>

namespace lb::app {

// Creates the parent folder of `path` if needed and checks that it takes a new file; throws
// std::runtime_error naming the path.
void prepare_output_path(const std::string& path);

// Refuses (std::runtime_error naming the path) when the file system of `path`'s folder (of
// `path` itself when it is a folder: a bake's) has less free space than `bytes`, the output's
// estimate: a full disk is found before the work.
void require_free_space(const std::string& path, double bytes);

// The most an image of width x height takes on disk with its JSON report (32-bit float RGBA
// EXR, uncompressed, plus 64 KiB): the estimate render, reference and snapshot check.
double image_output_bytes(int width, int height);

// prepare_output_path, and refuses (std::runtime_error naming the path) to replace an
// existing file that lightbake did not write, unless `force`.
void prepare_output_file(const std::string& path, bool force);

// An image stamped by bake/io/image_io, a JSON report whose "generator" is lightbake, a glTF
// whose asset.generator is lightbake, or a shard of any kind (bake/shards), by their magic.
bool written_by_lightbake(const std::string& path);

}  // namespace lb::app
