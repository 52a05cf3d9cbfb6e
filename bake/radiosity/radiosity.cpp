#include "bake/radiosity/radiosity.h"
