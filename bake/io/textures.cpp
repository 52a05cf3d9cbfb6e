#include "bake/io/textures.h"
