#include "bake/io/shapes.h"
