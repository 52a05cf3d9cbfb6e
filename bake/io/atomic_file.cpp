#include "bake/io/atomic_file.h"
