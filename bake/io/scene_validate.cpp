#include "bake/io/scene_load.h"
