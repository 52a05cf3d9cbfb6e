#include "bake/pipeline/bake.h"
