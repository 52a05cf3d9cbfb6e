#include "bake/io/image_io.h"
