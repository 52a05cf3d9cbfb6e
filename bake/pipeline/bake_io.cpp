#include "bake/pipeline/bake_io.h"
