#include "bake/io/mesh_files.h"
