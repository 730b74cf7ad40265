#pragma once

// tinygltf as Dualform uses it: no image decoding or encoding (images pass
// through a save as the bytes and URIs they were), no external image files
// read. Every file that includes tinygltf includes it through here, so all
// of them see the same configuration.
#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#include <tiny_gltf.h>
