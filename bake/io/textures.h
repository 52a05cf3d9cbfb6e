#pragma once
// Decoding texture files (the formats read_image reads, image_io.h) into lb::Texture.
// Shared by the native and the glTF loaders.

#include <string>

#include "bake/scene.h"

namespace lb {

// Reads an image file. Colour textures (`srgb` true) have their RGB channels decoded from sRGB
// to linear unless the file already holds linear floats (EXR, HDR); alpha and data textures
// (height and normal maps, `srgb` false) keep the file's values. Throws SceneError naming
// `where` (e.g. "scene.toml:12:5: materials.wall.texture") and the file when it fails.
Texture load_texture_file(const std::string& path, bool srgb, const std::string& where);

// An equirect sky image (bake/scene.h's convention) turned by `degrees` about +Y, right-handed
// (counterclockwise seen from above): what the image showed at azimuth phi it shows at phi +
// degrees. Columns are rolled, by linear interpolation between the two nearest (exact for a
// multiple of 360 / width degrees).
Texture rotated_equirect(const Texture& sky, double degrees);

// Same, from an encoded image in memory (e.g. a glTF buffer view); `name` is used in messages.
Texture load_texture_memory(const void* data, size_t size, const std::string& name, bool srgb,
                            const std::string& where);

}  // namespace lb
