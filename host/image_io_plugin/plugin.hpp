// The image plug-in's parts (host/image/image_io.hpp): each fills its functions into the table.
#pragma once
#include "image/image_io.hpp"

namespace shadelab::image_io {

void fill_oiio(Plugin& p);   // oiio.cpp
void fill_gdal(Plugin& p);   // gdal.cpp

// The program's services (plugin.cpp keeps the pointer the entry point was given).
const Host& host();

}  // namespace shadelab::image_io
