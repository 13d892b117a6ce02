// Deliberately wrong: the layering test checks this file as part of the
// lattice module, which may not use the elastic system (module system).
#include "lem/system/elastic_system.hpp"
