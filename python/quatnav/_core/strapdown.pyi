"""
NED strapdown mechanization (see quatnav/nav/strapdown.hpp)
"""
from __future__ import annotations
import numpy
import numpy.typing
import typing
__all__: list[str] = ['StrapdownState_f32', 'StrapdownState_f64', 'strapdown_batch', 'strapdown_step']
class StrapdownState_f64:
    """
    Strapdown navigation state: q_nb [w, x, y, z], v_n (m/s), lat, lon (rad), h (m) (double), and the previous increments dtheta_prev (rad), dv_prev (m/s), has_prev.
    """
    has_prev: bool
    def __init__(self, q_nb: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[4, 1]"], v_n: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], lat: typing.SupportsFloat | typing.SupportsIndex, lon: typing.SupportsFloat | typing.SupportsIndex, h: typing.SupportsFloat | typing.SupportsIndex) -> None:
        ...
    def copy(self) -> StrapdownState_f64:
        ...
    @property
    def dtheta_prev(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[3, 1]"]:
        ...
    @dtheta_prev.setter
    def dtheta_prev(self, arg0: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"]) -> None:
        ...
    @property
    def dv_prev(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[3, 1]"]:
        ...
    @dv_prev.setter
    def dv_prev(self, arg0: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"]) -> None:
        ...
    @property
    def h(self) -> float:
        ...
    @h.setter
    def h(self, arg0: typing.SupportsFloat | typing.SupportsIndex) -> None:
        ...
    @property
    def lat(self) -> float:
        ...
    @lat.setter
    def lat(self, arg0: typing.SupportsFloat | typing.SupportsIndex) -> None:
        ...
    @property
    def lon(self) -> float:
        ...
    @lon.setter
    def lon(self, arg0: typing.SupportsFloat | typing.SupportsIndex) -> None:
        ...
    @property
    def q_nb(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[4, 1]"]:
        ...
    @q_nb.setter
    def q_nb(self, arg0: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[4, 1]"]) -> None:
        ...
    @property
    def v_n(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[3, 1]"]:
        ...
    @v_n.setter
    def v_n(self, arg0: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"]) -> None:
        ...
class StrapdownState_f32:
    """
    Strapdown navigation state: q_nb [w, x, y, z], v_n (m/s), lat, lon (rad), h (m) (double), and the previous increments dtheta_prev (rad), dv_prev (m/s), has_prev.
    """
    has_prev: bool
    def __init__(self, q_nb: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[4, 1]"], v_n: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], lat: typing.SupportsFloat | typing.SupportsIndex, lon: typing.SupportsFloat | typing.SupportsIndex, h: typing.SupportsFloat | typing.SupportsIndex) -> None:
        ...
    def copy(self) -> StrapdownState_f32:
        ...
    @property
    def dtheta_prev(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float32], "[3, 1]"]:
        ...
    @dtheta_prev.setter
    def dtheta_prev(self, arg0: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"]) -> None:
        ...
    @property
    def dv_prev(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float32], "[3, 1]"]:
        ...
    @dv_prev.setter
    def dv_prev(self, arg0: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"]) -> None:
        ...
    @property
    def h(self) -> float:
        ...
    @h.setter
    def h(self, arg0: typing.SupportsFloat | typing.SupportsIndex) -> None:
        ...
    @property
    def lat(self) -> float:
        ...
    @lat.setter
    def lat(self, arg0: typing.SupportsFloat | typing.SupportsIndex) -> None:
        ...
    @property
    def lon(self) -> float:
        ...
    @lon.setter
    def lon(self, arg0: typing.SupportsFloat | typing.SupportsIndex) -> None:
        ...
    @property
    def q_nb(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float32], "[4, 1]"]:
        ...
    @q_nb.setter
    def q_nb(self, arg0: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[4, 1]"]) -> None:
        ...
    @property
    def v_n(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float32], "[3, 1]"]:
        ...
    @v_n.setter
    def v_n(self, arg0: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"]) -> None:
        ...
@typing.overload
def strapdown_batch(state: StrapdownState_f64, omega_ib_b: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], f_ib_b: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], dt: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], earth_rotation: bool = True) -> tuple[numpy.typing.NDArray[numpy.float64], numpy.typing.NDArray[numpy.float64], numpy.typing.NDArray[numpy.float64], numpy.typing.NDArray[numpy.uint8]]:
    """
    Run N steps in C++ with the GIL released (state updated in place). Returns (q_nb (N, 4), v_n (N, 3), llh (N, 3) float64 [lat, lon, h], status (N,) uint8 quatnav::Status).
    """
@typing.overload
def strapdown_batch(state: StrapdownState_f32, omega_ib_b: typing.Annotated[numpy.typing.ArrayLike, numpy.float32], f_ib_b: typing.Annotated[numpy.typing.ArrayLike, numpy.float32], dt: typing.Annotated[numpy.typing.ArrayLike, numpy.float32], earth_rotation: bool = True) -> tuple[numpy.typing.NDArray[numpy.float32], numpy.typing.NDArray[numpy.float32], numpy.typing.NDArray[numpy.float64], numpy.typing.NDArray[numpy.uint8]]:
    """
    Run N steps in C++ with the GIL released (state updated in place). Returns (q_nb (N, 4), v_n (N, 3), llh (N, 3) float64 [lat, lon, h], status (N,) uint8 quatnav::Status).
    """
@typing.overload
def strapdown_step(state: StrapdownState_f64, omega_ib_b: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], f_ib_b: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], dt: typing.SupportsFloat | typing.SupportsIndex, earth_rotation: bool = True) -> str:
    """
    One step (in place). Inputs are the mean rate and specific force over the interval. Returns the status string; the state is untouched unless it is 'ok'.
    """
@typing.overload
def strapdown_step(state: StrapdownState_f32, omega_ib_b: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], f_ib_b: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], dt: typing.SupportsFloat | typing.SupportsIndex, earth_rotation: bool = True) -> str:
    """
    One step (in place). Inputs are the mean rate and specific force over the interval. Returns the status string; the state is untouched unless it is 'ok'.
    """
