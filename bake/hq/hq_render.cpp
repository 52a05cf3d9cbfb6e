#include "bake/hq/hq_render.h"
