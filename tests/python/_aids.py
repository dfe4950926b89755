"""GPS/INS aids given as arrays (gps_t, gps_llh, ...) as the Aid keywords of GpsInsFilter.run (the public
class's and its numpy twin's)."""
import quatnav


def as_aids(kw: dict) -> dict:
    out = {}
    if kw.get("gps_t") is not None:
        out["gps_pos"] = quatnav.Aid(kw["gps_t"], kw["gps_llh"], kw.get("gps_pos_sigma"))
        if kw.get("gps_vel") is not None:
            out["gps_vel"] = quatnav.Aid(kw["gps_t"], kw["gps_vel"], kw.get("gps_vel_sigma"))
    if kw.get("baro_t") is not None:
        out["baro"] = quatnav.Aid(kw["baro_t"], kw["baro_h"])
    if kw.get("compass_t") is not None:
        out["compass"] = quatnav.Aid(kw["compass_t"], kw["compass_yaw"])
    for k in ("outages", "on_invalid"):
        if k in kw:
            out[k] = kw[k]
    return out
