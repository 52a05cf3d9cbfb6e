#include "bake/radiosity/patches.h"
