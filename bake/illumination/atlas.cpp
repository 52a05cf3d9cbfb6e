#include "bake/illumination/atlas.h"
