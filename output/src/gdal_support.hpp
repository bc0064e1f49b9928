#pragma once
// What the GDAL-based writers share: the drivers registered once, and
// GDAL's last error for our messages (its handler is kept quiet meanwhile
// with CPLErrorHandlerPusher(CPLQuietErrorHandler)).

#include <cpl_error.h>
#include <gdal_priv.h>

#include <mutex>
#include <string>

namespace sage::output {

inline void register_gdal() {
  static std::once_flag registered;
  std::call_once(registered, [] { GDALAllRegister(); });
}

inline std::string gdal_message() {
  const char* m = CPLGetLastErrorMsg();
  return m && *m ? m : "no details from GDAL";
}

}  // namespace sage::output
