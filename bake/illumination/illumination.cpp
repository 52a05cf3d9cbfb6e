#include "bake/illumination/illumination.h"
