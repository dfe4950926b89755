"""
quatnav compiled core (header-only C++ filters bound for float32 and float64)
"""
from __future__ import annotations
import numpy
import numpy.typing
import typing
from . import quat
from . import earth
from . import strapdown
__all__: list[str] = ['AccFilterParams_f32', 'AccFilterParams_f64', 'EulerEKFParams_f32', 'EulerEKFParams_f64', 'EulerEKF_f32', 'EulerEKF_f64', 'GpsInsFilterScale_f32', 'GpsInsFilterScale_f64', 'GpsInsFilter_f32', 'GpsInsFilter_f64', 'GpsInsParams_f32', 'GpsInsParams_f64', 'GpsInsUpdate1_f32', 'GpsInsUpdate1_f64', 'GpsInsUpdate2_f32', 'GpsInsUpdate2_f64', 'GpsInsUpdate3_f32', 'GpsInsUpdate3_f64', 'GyroClipParams_f32', 'GyroClipParams_f64', 'MagDisturbanceParams_f32', 'MagDisturbanceParams_f64', 'MargFilterParams_f32', 'MargFilterParams_f64', 'MargFilter_f32', 'MargFilter_f64', 'MargUpdateResult_f32', 'MargUpdateResult_f64', 'NavFilter13Ekf_f32', 'NavFilter13Ekf_f64', 'NavFilter13Params_f32', 'NavFilter13Params_f64', 'NavFilter13SecondOrder_f32', 'NavFilter13SecondOrder_f64', 'NavFilter13Ukf_f32', 'NavFilter13Ukf_f64', 'QuaternionEKFPaper_f32', 'QuaternionEKFPaper_f64', 'QuaternionEKFParams_f32', 'QuaternionEKFParams_f64', 'QuaternionEKF_f32', 'QuaternionEKF_f64', 'RestParams_f32', 'RestParams_f64', 'UpdateResult1_f32', 'UpdateResult1_f64', 'UpdateResult3_f32', 'UpdateResult3_f64', 'UpdateResult4_f32', 'UpdateResult4_f64', 'UpdateResult6_f32', 'UpdateResult6_f64', 'compiler', 'earth', 'first_zero_norm_row', 'flag_table', 'gnss_solution_names', 'gpsins_decision_names', 'nav13_time_update_cost_ns', 'quat', 'status_names', 'strapdown']
class UpdateResult3_f64:
    """
    Outcome of one measurement update.
    """
    def __repr__(self) -> str:
        ...
    @property
    def accepted(self) -> bool:
        ...
    @property
    def innovation(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[3, 1]"]:
        ...
    @property
    def innovation_cov(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[3, 3]"]:
        ...
    @property
    def nis(self) -> float:
        ...
    @property
    def status(self) -> str:
        ...
class UpdateResult6_f64:
    """
    Outcome of one measurement update.
    """
    def __repr__(self) -> str:
        ...
    @property
    def accepted(self) -> bool:
        ...
    @property
    def innovation(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[6, 1]"]:
        ...
    @property
    def innovation_cov(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[6, 6]"]:
        ...
    @property
    def nis(self) -> float:
        ...
    @property
    def status(self) -> str:
        ...
class RestParams_f64:
    """
    Rest detection (attitude/parts/rest.hpp).
    """
    @staticmethod
    def fields() -> list:
        """
        The declaration table: a list of (name, default, unit, doc).
        """
    @staticmethod
    def from_dict(d: dict) -> RestParams_f64:
        """
        From a dict of some fields (the others keep their defaults); unknown keys refused.
        """
    def __init__(self) -> None:
        ...
    def __repr__(self) -> str:
        ...
    def to_dict(self) -> dict:
        ...
    @property
    def rest_acc_th(self) -> float:
        """
        rest: largest deviation of the low-passed accelerometer [m/s^2]
        """
    @rest_acc_th.setter
    def rest_acc_th(self, arg1: typing.Any) -> None:
        ...
    @property
    def rest_detection(self) -> bool:
        """
        detect rest and use it as a zero-rate measurement of the gyro bias [-]
        """
    @rest_detection.setter
    def rest_detection(self, arg1: typing.Any) -> None:
        ...
    @property
    def rest_gyr_th(self) -> float:
        """
        rest: largest deviation of the low-passed gyro [rad/s]
        """
    @rest_gyr_th.setter
    def rest_gyr_th(self, arg1: typing.Any) -> None:
        ...
    @property
    def rest_rate_noise(self) -> float:
        """
        std of the residual rate at rest [rad/s]
        """
    @rest_rate_noise.setter
    def rest_rate_noise(self, arg1: typing.Any) -> None:
        ...
    @property
    def rest_tau(self) -> float:
        """
        rest: low-pass time constant [s]
        """
    @rest_tau.setter
    def rest_tau(self, arg1: typing.Any) -> None:
        ...
    @property
    def rest_time(self) -> float:
        """
        rest: shortest duration [s]
        """
    @rest_time.setter
    def rest_time(self, arg1: typing.Any) -> None:
        ...
class AccFilterParams_f64:
    """
    The accelerometer part (attitude/parts/acc_filter.hpp).
    """
    @staticmethod
    def fields() -> list:
        """
        The declaration table: a list of (name, default, unit, doc).
        """
    @staticmethod
    def from_dict(d: dict) -> AccFilterParams_f64:
        """
        From a dict of some fields (the others keep their defaults); unknown keys refused.
        """
    def __init__(self) -> None:
        ...
    def __repr__(self) -> str:
        ...
    def to_dict(self) -> dict:
        ...
    @property
    def acc_adapt(self) -> float:
        """
        adaptive accelerometer noise: std acc_sigma + acc_adapt * ||a|-g|/g [1]
        """
    @acc_adapt.setter
    def acc_adapt(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_bias_dev(self) -> float:
        """
        the accelerometer's weight in the gyro-bias block falls as 1 / (1 + (dev_lp / acc_bias_dev)^2), dev_lp the low-passed ||a|-g| of the raw samples (0: off) [m/s^2]
        """
    @acc_bias_dev.setter
    def acc_bias_dev(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_lp_bias_sigma(self) -> float:
        """
        above this gyro-bias one-sigma the accelerometer low-pass time constant shrinks by (acc_lp_bias_sigma / sigma_b)^2 (0: off) [rad/s]
        """
    @acc_lp_bias_sigma.setter
    def acc_lp_bias_sigma(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_lp_dev(self) -> float:
        """
        the shrink of acc_lp_bias_sigma fades out as the low-passed ||a|-g| of the raw samples approaches this (0: off) [m/s^2]
        """
    @acc_lp_dev.setter
    def acc_lp_dev(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_lp_tau(self) -> float:
        """
        low-pass time constant of the accelerometer in a quasi-inertial frame (0: off) [s]
        """
    @acc_lp_tau.setter
    def acc_lp_tau(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_recovery_time(self) -> float:
        """
        after this long with every accelerometer update rejected, accept again (0: never) [s]
        """
    @acc_recovery_time.setter
    def acc_recovery_time(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_reject(self) -> float:
        """
        reject the accelerometer when ||a|-g| exceeds it (0: off) [m/s^2]
        """
    @acc_reject.setter
    def acc_reject(self, arg1: typing.Any) -> None:
        ...
    @property
    def gravity(self) -> float:
        """
        magnitude of gravity, in the unit of acc [m/s^2]
        """
    @gravity.setter
    def gravity(self, arg1: typing.Any) -> None:
        ...
class MagDisturbanceParams_f64:
    """
    The magnetometer part (attitude/parts/mag_disturbance.hpp).
    """
    @staticmethod
    def fields() -> list:
        """
        The declaration table: a list of (name, default, unit, doc).
        """
    @staticmethod
    def from_dict(d: dict) -> MagDisturbanceParams_f64:
        """
        From a dict of some fields (the others keep their defaults); unknown keys refused.
        """
    def __init__(self) -> None:
        ...
    def __repr__(self) -> str:
        ...
    def to_dict(self) -> dict:
        ...
    @property
    def mag_dip_tol(self) -> float:
        """
        reject the magnetometer when its dip differs from the reference by more (0: off) [rad]
        """
    @mag_dip_tol.setter
    def mag_dip_tol(self, arg1: typing.Any) -> None:
        ...
    @property
    def mag_norm_tol(self) -> float:
        """
        reject the magnetometer when ||m|/m_ref - 1| exceeds it (0: off) [1]
        """
    @mag_norm_tol.setter
    def mag_norm_tol(self, arg1: typing.Any) -> None:
        ...
    @property
    def mag_recovery_time(self) -> float:
        """
        after this long with every sample disturbed, the field becomes the reference (0: never) [s]
        """
    @mag_recovery_time.setter
    def mag_recovery_time(self, arg1: typing.Any) -> None:
        ...
    @property
    def mag_ref_samples(self) -> int:
        """
        magnetometer samples over which the reference dip is averaged [1]
        """
    @mag_ref_samples.setter
    def mag_ref_samples(self, arg1: typing.Any) -> None:
        ...
    @property
    def mag_ref_tau(self) -> float:
        """
        time constant with which the reference norm and dip follow the field [s]
        """
    @mag_ref_tau.setter
    def mag_ref_tau(self, arg1: typing.Any) -> None:
        ...
    @property
    def mag_settle_time(self) -> float:
        """
        after a disturbance, the field must pass the tests this long [s]
        """
    @mag_settle_time.setter
    def mag_settle_time(self, arg1: typing.Any) -> None:
        ...
class GyroClipParams_f64:
    """
    Clipped gyro readings (attitude/parts/gyro_clip.hpp).
    """
    @staticmethod
    def fields() -> list:
        """
        The declaration table: a list of (name, default, unit, doc).
        """
    @staticmethod
    def from_dict(d: dict) -> GyroClipParams_f64:
        """
        From a dict of some fields (the others keep their defaults); unknown keys refused.
        """
    def __init__(self) -> None:
        ...
    def __repr__(self) -> str:
        ...
    def to_dict(self) -> dict:
        ...
    @property
    def gyro_clip(self) -> bool:
        """
        recognize clipped gyro readings (an axis stuck at the largest magnitude seen) and distrust them [-]
        """
    @gyro_clip.setter
    def gyro_clip(self, arg1: typing.Any) -> None:
        ...
    @property
    def gyro_clip_min_rate(self) -> float:
        """
        smallest reading taken for a clip [rad/s]
        """
    @gyro_clip_min_rate.setter
    def gyro_clip_min_rate(self, arg1: typing.Any) -> None:
        ...
    @property
    def gyro_clip_noise(self) -> float:
        """
        std of a clipped step's attitude error about that axis, as a fraction of reading times dt [1]
        """
    @gyro_clip_noise.setter
    def gyro_clip_noise(self, arg1: typing.Any) -> None:
        ...
    @property
    def gyro_clip_repeats(self) -> int:
        """
        a clip: the reading repeats this many previous readings exactly [1]
        """
    @gyro_clip_repeats.setter
    def gyro_clip_repeats(self, arg1: typing.Any) -> None:
        ...
class QuaternionEKFParams_f64:
    """
    Parameters of QuaternionEKF and of its paper form QuaternionEKFPaper (quaternion_ekf_params.hpp).
    """
    @staticmethod
    def fields() -> list:
        """
        The declaration table: a list of (name, default, unit, doc).
        """
    @staticmethod
    def from_dict(d: dict) -> QuaternionEKFParams_f64:
        """
        From a dict of some fields (the others keep their defaults); unknown keys refused.
        """
    @staticmethod
    def paper() -> QuaternionEKFParams_f64:
        """
        Parameters of the plain paper-000 filter (robustness off).
        """
    def __init__(self) -> None:
        ...
    def __repr__(self) -> str:
        ...
    def to_dict(self) -> dict:
        ...
    @property
    def acc_adapt(self) -> float:
        """
        adaptive accelerometer noise: std acc_sigma + acc_adapt * ||a|-g|/g [1]
        """
    @acc_adapt.setter
    def acc_adapt(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_bias_dev(self) -> float:
        """
        the accelerometer's weight in the gyro-bias block falls as 1 / (1 + (dev_lp / acc_bias_dev)^2), dev_lp the low-passed ||a|-g| of the raw samples (0: off) [m/s^2]
        """
    @acc_bias_dev.setter
    def acc_bias_dev(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_gate(self) -> float:
        """
        NIS gate of the accelerometer update (0: off) [1 (chi-square, 3 dof)]
        """
    @acc_gate.setter
    def acc_gate(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_lp_bias_sigma(self) -> float:
        """
        above this gyro-bias one-sigma the accelerometer low-pass time constant shrinks by (acc_lp_bias_sigma / sigma_b)^2 (0: off) [rad/s]
        """
    @acc_lp_bias_sigma.setter
    def acc_lp_bias_sigma(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_lp_dev(self) -> float:
        """
        the shrink of acc_lp_bias_sigma fades out as the low-passed ||a|-g| of the raw samples approaches this (0: off) [m/s^2]
        """
    @acc_lp_dev.setter
    def acc_lp_dev(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_lp_tau(self) -> float:
        """
        low-pass time constant of the accelerometer in a quasi-inertial frame (0: off) [s]
        """
    @acc_lp_tau.setter
    def acc_lp_tau(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_range(self) -> float:
        """
        accelerometer range per axis, as gyro_range (0: unlimited) [m/s^2]
        """
    @acc_range.setter
    def acc_range(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_recovery_time(self) -> float:
        """
        after this long with every accelerometer update rejected, accept again (0: never) [s]
        """
    @acc_recovery_time.setter
    def acc_recovery_time(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_reject(self) -> float:
        """
        reject the accelerometer when ||a|-g| exceeds it (0: off) [m/s^2]
        """
    @acc_reject.setter
    def acc_reject(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_sigma(self) -> float:
        """
        std of each component of the normalized accelerometer [1 (normalized)]
        """
    @acc_sigma.setter
    def acc_sigma(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_tilt_only(self) -> bool:
        """
        the accelerometer corrects the tilt and the horizontal gyro bias only (false: the optimal gain) [-]
        """
    @acc_tilt_only.setter
    def acc_tilt_only(self, arg1: typing.Any) -> None:
        ...
    @property
    def cov_floor(self) -> float:
        """
        eigenvalue floor of the error covariance (0: off) [state units^2]
        """
    @cov_floor.setter
    def cov_floor(self, arg1: typing.Any) -> None:
        ...
    @property
    def declination(self) -> float:
        """
        magnetic declination, east of true north (0: x is magnetic north) [rad]
        """
    @declination.setter
    def declination(self, arg1: typing.Any) -> None:
        ...
    @property
    def gravity(self) -> float:
        """
        magnitude of gravity, in the unit of acc [m/s^2]
        """
    @gravity.setter
    def gravity(self, arg1: typing.Any) -> None:
        ...
    @property
    def gyro_bias_noise(self) -> float:
        """
        gyro-bias random-walk density [rad/s^2/sqrt(Hz)]
        """
    @gyro_bias_noise.setter
    def gyro_bias_noise(self, arg1: typing.Any) -> None:
        ...
    @property
    def gyro_clip(self) -> bool:
        """
        recognize clipped gyro readings (an axis stuck at the largest magnitude seen) and distrust them [-]
        """
    @gyro_clip.setter
    def gyro_clip(self, arg1: typing.Any) -> None:
        ...
    @property
    def gyro_clip_min_rate(self) -> float:
        """
        smallest reading taken for a clip [rad/s]
        """
    @gyro_clip_min_rate.setter
    def gyro_clip_min_rate(self, arg1: typing.Any) -> None:
        ...
    @property
    def gyro_clip_noise(self) -> float:
        """
        std of a clipped step's attitude error about that axis, as a fraction of reading times dt [1]
        """
    @gyro_clip_noise.setter
    def gyro_clip_noise(self, arg1: typing.Any) -> None:
        ...
    @property
    def gyro_clip_repeats(self) -> int:
        """
        a clip: the reading repeats this many previous readings exactly [1]
        """
    @gyro_clip_repeats.setter
    def gyro_clip_repeats(self, arg1: typing.Any) -> None:
        ...
    @property
    def gyro_noise(self) -> float:
        """
        gyro white-noise density (angle random walk) [rad/s/sqrt(Hz)]
        """
    @gyro_noise.setter
    def gyro_noise(self, arg1: typing.Any) -> None:
        ...
    @property
    def gyro_range(self) -> float:
        """
        gyro range per axis: a reading at or above it is saturated and its step skipped (0: unlimited) [rad/s]
        """
    @gyro_range.setter
    def gyro_range(self, arg1: typing.Any) -> None:
        ...
    @property
    def gyro_rate_noise(self) -> float:
        """
        rate-proportional attitude process noise: density gyro_rate_noise * |w - b| (0: off); the attitude filters apply it to the tilt only [1/sqrt(Hz)]
        """
    @gyro_rate_noise.setter
    def gyro_rate_noise(self, arg1: typing.Any) -> None:
        ...
    @property
    def init_att_sigma(self) -> float:
        """
        attitude one-sigma after initialize [rad]
        """
    @init_att_sigma.setter
    def init_att_sigma(self, arg1: typing.Any) -> None:
        ...
    @property
    def init_gyro_bias_sigma(self) -> float:
        """
        gyro-bias one-sigma after initialize [rad/s]
        """
    @init_gyro_bias_sigma.setter
    def init_gyro_bias_sigma(self, arg1: typing.Any) -> None:
        ...
    @property
    def mag_dip_tol(self) -> float:
        """
        reject the magnetometer when its dip differs from the reference by more (0: off) [rad]
        """
    @mag_dip_tol.setter
    def mag_dip_tol(self, arg1: typing.Any) -> None:
        ...
    @property
    def mag_gate(self) -> float:
        """
        NIS gate of the magnetometer update (0: off) [1 (chi-square)]
        """
    @mag_gate.setter
    def mag_gate(self, arg1: typing.Any) -> None:
        ...
    @property
    def mag_heading_only(self) -> bool:
        """
        the magnetometer corrects heading only (false: 3-row update) [-]
        """
    @mag_heading_only.setter
    def mag_heading_only(self, arg1: typing.Any) -> None:
        ...
    @property
    def mag_norm_tol(self) -> float:
        """
        reject the magnetometer when ||m|/m_ref - 1| exceeds it (0: off) [1]
        """
    @mag_norm_tol.setter
    def mag_norm_tol(self, arg1: typing.Any) -> None:
        ...
    @property
    def mag_recovery_time(self) -> float:
        """
        after this long with every sample disturbed, the field becomes the reference (0: never) [s]
        """
    @mag_recovery_time.setter
    def mag_recovery_time(self, arg1: typing.Any) -> None:
        ...
    @property
    def mag_ref_samples(self) -> int:
        """
        magnetometer samples over which the reference dip is averaged [1]
        """
    @mag_ref_samples.setter
    def mag_ref_samples(self, arg1: typing.Any) -> None:
        ...
    @property
    def mag_ref_tau(self) -> float:
        """
        time constant with which the reference norm and dip follow the field [s]
        """
    @mag_ref_tau.setter
    def mag_ref_tau(self, arg1: typing.Any) -> None:
        ...
    @property
    def mag_settle_time(self) -> float:
        """
        after a disturbance, the field must pass the tests this long [s]
        """
    @mag_settle_time.setter
    def mag_settle_time(self, arg1: typing.Any) -> None:
        ...
    @property
    def mag_sigma(self) -> float:
        """
        std of each component of the normalized magnetometer [1 (normalized)]
        """
    @mag_sigma.setter
    def mag_sigma(self, arg1: typing.Any) -> None:
        ...
    @property
    def max_dt(self) -> float:
        """
        longest accepted IMU step [s]
        """
    @max_dt.setter
    def max_dt(self, arg1: typing.Any) -> None:
        ...
    @property
    def rest_acc_th(self) -> float:
        """
        rest: largest deviation of the low-passed accelerometer [m/s^2]
        """
    @rest_acc_th.setter
    def rest_acc_th(self, arg1: typing.Any) -> None:
        ...
    @property
    def rest_detection(self) -> bool:
        """
        detect rest and use it as a zero-rate measurement of the gyro bias [-]
        """
    @rest_detection.setter
    def rest_detection(self, arg1: typing.Any) -> None:
        ...
    @property
    def rest_gyr_th(self) -> float:
        """
        rest: largest deviation of the low-passed gyro [rad/s]
        """
    @rest_gyr_th.setter
    def rest_gyr_th(self, arg1: typing.Any) -> None:
        ...
    @property
    def rest_rate_noise(self) -> float:
        """
        std of the residual rate at rest [rad/s]
        """
    @rest_rate_noise.setter
    def rest_rate_noise(self, arg1: typing.Any) -> None:
        ...
    @property
    def rest_tau(self) -> float:
        """
        rest: low-pass time constant [s]
        """
    @rest_tau.setter
    def rest_tau(self, arg1: typing.Any) -> None:
        ...
    @property
    def rest_time(self) -> float:
        """
        rest: shortest duration [s]
        """
    @rest_time.setter
    def rest_time(self, arg1: typing.Any) -> None:
        ...
class QuaternionEKFPaper_f64:
    @staticmethod
    def state_fields() -> list:
        """
        The state's declaration table: (name, default, unit, doc).
        """
    def __init__(self, params: QuaternionEKFParams_f64) -> None:
        ...
    def get_state(self) -> dict:
        """
        The complete state as a dict of arrays and numbers (set_state restores it exactly).
        """
    def initialize(self, acc: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], mag: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"] | None = None) -> str:
        ...
    def predict(self, gyr: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], dt: typing.SupportsFloat | typing.SupportsIndex) -> str:
        ...
    def reset(self, q_nb: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[4, 1]"], gyro_bias: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], P: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[7, 7]"]) -> str:
        ...
    def run(self, gyr: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], acc: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], mag: typing.Any, dt: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], smooth: bool = False, segment: typing.SupportsInt | typing.SupportsIndex = 256) -> tuple:
        """
        Batch run (GIL released). Returns (quat, bias, sigma, att_sigma, flags); with smooth, a sixth item: the Rauch-Tung-Striebel estimates (quat, bias, sigma, att_sigma) and the smoother's 'info'.
        """
    def set_mag_dip(self, dip: typing.SupportsFloat | typing.SupportsIndex) -> None:
        ...
    def set_state(self, state: dict) -> str:
        """
        Restore a state from get_state(); unknown and missing keys are refused.
        """
    def update_acc(self, acc: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], gate: typing.SupportsFloat | typing.SupportsIndex = 0.0) -> UpdateResult3_f64:
        ...
    def update_acc_mag(self, acc: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], mag: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], gate: typing.SupportsFloat | typing.SupportsIndex = 0.0) -> UpdateResult6_f64:
        ...
    def update_mag(self, mag: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], gate: typing.SupportsFloat | typing.SupportsIndex = 0.0) -> UpdateResult3_f64:
        ...
    @property
    def at_rest(self) -> bool:
        ...
    @property
    def attitude_covariance(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[3, 3]"]:
        ...
    @property
    def bias(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[3, 1]"]:
        """
        gyro bias [rad/s]
        """
    @property
    def covariance(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[7, 7]"]:
        ...
    @property
    def extra_flags(self) -> int:
        ...
    @property
    def initialized(self) -> bool:
        ...
    @property
    def params(self) -> QuaternionEKFParams_f64:
        ...
    @property
    def quat(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[4, 1]"]:
        """
        q_nb [w, x, y, z]
        """
class UpdateResult3_f32:
    """
    Outcome of one measurement update.
    """
    def __repr__(self) -> str:
        ...
    @property
    def accepted(self) -> bool:
        ...
    @property
    def innovation(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float32], "[3, 1]"]:
        ...
    @property
    def innovation_cov(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float32], "[3, 3]"]:
        ...
    @property
    def nis(self) -> float:
        ...
    @property
    def status(self) -> str:
        ...
class UpdateResult6_f32:
    """
    Outcome of one measurement update.
    """
    def __repr__(self) -> str:
        ...
    @property
    def accepted(self) -> bool:
        ...
    @property
    def innovation(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float32], "[6, 1]"]:
        ...
    @property
    def innovation_cov(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float32], "[6, 6]"]:
        ...
    @property
    def nis(self) -> float:
        ...
    @property
    def status(self) -> str:
        ...
class RestParams_f32:
    """
    Rest detection (attitude/parts/rest.hpp).
    """
    @staticmethod
    def fields() -> list:
        """
        The declaration table: a list of (name, default, unit, doc).
        """
    @staticmethod
    def from_dict(d: dict) -> RestParams_f32:
        """
        From a dict of some fields (the others keep their defaults); unknown keys refused.
        """
    def __init__(self) -> None:
        ...
    def __repr__(self) -> str:
        ...
    def to_dict(self) -> dict:
        ...
    @property
    def rest_acc_th(self) -> float:
        """
        rest: largest deviation of the low-passed accelerometer [m/s^2]
        """
    @rest_acc_th.setter
    def rest_acc_th(self, arg1: typing.Any) -> None:
        ...
    @property
    def rest_detection(self) -> bool:
        """
        detect rest and use it as a zero-rate measurement of the gyro bias [-]
        """
    @rest_detection.setter
    def rest_detection(self, arg1: typing.Any) -> None:
        ...
    @property
    def rest_gyr_th(self) -> float:
        """
        rest: largest deviation of the low-passed gyro [rad/s]
        """
    @rest_gyr_th.setter
    def rest_gyr_th(self, arg1: typing.Any) -> None:
        ...
    @property
    def rest_rate_noise(self) -> float:
        """
        std of the residual rate at rest [rad/s]
        """
    @rest_rate_noise.setter
    def rest_rate_noise(self, arg1: typing.Any) -> None:
        ...
    @property
    def rest_tau(self) -> float:
        """
        rest: low-pass time constant [s]
        """
    @rest_tau.setter
    def rest_tau(self, arg1: typing.Any) -> None:
        ...
    @property
    def rest_time(self) -> float:
        """
        rest: shortest duration [s]
        """
    @rest_time.setter
    def rest_time(self, arg1: typing.Any) -> None:
        ...
class AccFilterParams_f32:
    """
    The accelerometer part (attitude/parts/acc_filter.hpp).
    """
    @staticmethod
    def fields() -> list:
        """
        The declaration table: a list of (name, default, unit, doc).
        """
    @staticmethod
    def from_dict(d: dict) -> AccFilterParams_f32:
        """
        From a dict of some fields (the others keep their defaults); unknown keys refused.
        """
    def __init__(self) -> None:
        ...
    def __repr__(self) -> str:
        ...
    def to_dict(self) -> dict:
        ...
    @property
    def acc_adapt(self) -> float:
        """
        adaptive accelerometer noise: std acc_sigma + acc_adapt * ||a|-g|/g [1]
        """
    @acc_adapt.setter
    def acc_adapt(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_bias_dev(self) -> float:
        """
        the accelerometer's weight in the gyro-bias block falls as 1 / (1 + (dev_lp / acc_bias_dev)^2), dev_lp the low-passed ||a|-g| of the raw samples (0: off) [m/s^2]
        """
    @acc_bias_dev.setter
    def acc_bias_dev(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_lp_bias_sigma(self) -> float:
        """
        above this gyro-bias one-sigma the accelerometer low-pass time constant shrinks by (acc_lp_bias_sigma / sigma_b)^2 (0: off) [rad/s]
        """
    @acc_lp_bias_sigma.setter
    def acc_lp_bias_sigma(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_lp_dev(self) -> float:
        """
        the shrink of acc_lp_bias_sigma fades out as the low-passed ||a|-g| of the raw samples approaches this (0: off) [m/s^2]
        """
    @acc_lp_dev.setter
    def acc_lp_dev(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_lp_tau(self) -> float:
        """
        low-pass time constant of the accelerometer in a quasi-inertial frame (0: off) [s]
        """
    @acc_lp_tau.setter
    def acc_lp_tau(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_recovery_time(self) -> float:
        """
        after this long with every accelerometer update rejected, accept again (0: never) [s]
        """
    @acc_recovery_time.setter
    def acc_recovery_time(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_reject(self) -> float:
        """
        reject the accelerometer when ||a|-g| exceeds it (0: off) [m/s^2]
        """
    @acc_reject.setter
    def acc_reject(self, arg1: typing.Any) -> None:
        ...
    @property
    def gravity(self) -> float:
        """
        magnitude of gravity, in the unit of acc [m/s^2]
        """
    @gravity.setter
    def gravity(self, arg1: typing.Any) -> None:
        ...
class MagDisturbanceParams_f32:
    """
    The magnetometer part (attitude/parts/mag_disturbance.hpp).
    """
    @staticmethod
    def fields() -> list:
        """
        The declaration table: a list of (name, default, unit, doc).
        """
    @staticmethod
    def from_dict(d: dict) -> MagDisturbanceParams_f32:
        """
        From a dict of some fields (the others keep their defaults); unknown keys refused.
        """
    def __init__(self) -> None:
        ...
    def __repr__(self) -> str:
        ...
    def to_dict(self) -> dict:
        ...
    @property
    def mag_dip_tol(self) -> float:
        """
        reject the magnetometer when its dip differs from the reference by more (0: off) [rad]
        """
    @mag_dip_tol.setter
    def mag_dip_tol(self, arg1: typing.Any) -> None:
        ...
    @property
    def mag_norm_tol(self) -> float:
        """
        reject the magnetometer when ||m|/m_ref - 1| exceeds it (0: off) [1]
        """
    @mag_norm_tol.setter
    def mag_norm_tol(self, arg1: typing.Any) -> None:
        ...
    @property
    def mag_recovery_time(self) -> float:
        """
        after this long with every sample disturbed, the field becomes the reference (0: never) [s]
        """
    @mag_recovery_time.setter
    def mag_recovery_time(self, arg1: typing.Any) -> None:
        ...
    @property
    def mag_ref_samples(self) -> int:
        """
        magnetometer samples over which the reference dip is averaged [1]
        """
    @mag_ref_samples.setter
    def mag_ref_samples(self, arg1: typing.Any) -> None:
        ...
    @property
    def mag_ref_tau(self) -> float:
        """
        time constant with which the reference norm and dip follow the field [s]
        """
    @mag_ref_tau.setter
    def mag_ref_tau(self, arg1: typing.Any) -> None:
        ...
    @property
    def mag_settle_time(self) -> float:
        """
        after a disturbance, the field must pass the tests this long [s]
        """
    @mag_settle_time.setter
    def mag_settle_time(self, arg1: typing.Any) -> None:
        ...
class GyroClipParams_f32:
    """
    Clipped gyro readings (attitude/parts/gyro_clip.hpp).
    """
    @staticmethod
    def fields() -> list:
        """
        The declaration table: a list of (name, default, unit, doc).
        """
    @staticmethod
    def from_dict(d: dict) -> GyroClipParams_f32:
        """
        From a dict of some fields (the others keep their defaults); unknown keys refused.
        """
    def __init__(self) -> None:
        ...
    def __repr__(self) -> str:
        ...
    def to_dict(self) -> dict:
        ...
    @property
    def gyro_clip(self) -> bool:
        """
        recognize clipped gyro readings (an axis stuck at the largest magnitude seen) and distrust them [-]
        """
    @gyro_clip.setter
    def gyro_clip(self, arg1: typing.Any) -> None:
        ...
    @property
    def gyro_clip_min_rate(self) -> float:
        """
        smallest reading taken for a clip [rad/s]
        """
    @gyro_clip_min_rate.setter
    def gyro_clip_min_rate(self, arg1: typing.Any) -> None:
        ...
    @property
    def gyro_clip_noise(self) -> float:
        """
        std of a clipped step's attitude error about that axis, as a fraction of reading times dt [1]
        """
    @gyro_clip_noise.setter
    def gyro_clip_noise(self, arg1: typing.Any) -> None:
        ...
    @property
    def gyro_clip_repeats(self) -> int:
        """
        a clip: the reading repeats this many previous readings exactly [1]
        """
    @gyro_clip_repeats.setter
    def gyro_clip_repeats(self, arg1: typing.Any) -> None:
        ...
class QuaternionEKFParams_f32:
    """
    Parameters of QuaternionEKF and of its paper form QuaternionEKFPaper (quaternion_ekf_params.hpp).
    """
    @staticmethod
    def fields() -> list:
        """
        The declaration table: a list of (name, default, unit, doc).
        """
    @staticmethod
    def from_dict(d: dict) -> QuaternionEKFParams_f32:
        """
        From a dict of some fields (the others keep their defaults); unknown keys refused.
        """
    @staticmethod
    def paper() -> QuaternionEKFParams_f32:
        """
        Parameters of the plain paper-000 filter (robustness off).
        """
    def __init__(self) -> None:
        ...
    def __repr__(self) -> str:
        ...
    def to_dict(self) -> dict:
        ...
    @property
    def acc_adapt(self) -> float:
        """
        adaptive accelerometer noise: std acc_sigma + acc_adapt * ||a|-g|/g [1]
        """
    @acc_adapt.setter
    def acc_adapt(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_bias_dev(self) -> float:
        """
        the accelerometer's weight in the gyro-bias block falls as 1 / (1 + (dev_lp / acc_bias_dev)^2), dev_lp the low-passed ||a|-g| of the raw samples (0: off) [m/s^2]
        """
    @acc_bias_dev.setter
    def acc_bias_dev(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_gate(self) -> float:
        """
        NIS gate of the accelerometer update (0: off) [1 (chi-square, 3 dof)]
        """
    @acc_gate.setter
    def acc_gate(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_lp_bias_sigma(self) -> float:
        """
        above this gyro-bias one-sigma the accelerometer low-pass time constant shrinks by (acc_lp_bias_sigma / sigma_b)^2 (0: off) [rad/s]
        """
    @acc_lp_bias_sigma.setter
    def acc_lp_bias_sigma(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_lp_dev(self) -> float:
        """
        the shrink of acc_lp_bias_sigma fades out as the low-passed ||a|-g| of the raw samples approaches this (0: off) [m/s^2]
        """
    @acc_lp_dev.setter
    def acc_lp_dev(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_lp_tau(self) -> float:
        """
        low-pass time constant of the accelerometer in a quasi-inertial frame (0: off) [s]
        """
    @acc_lp_tau.setter
    def acc_lp_tau(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_range(self) -> float:
        """
        accelerometer range per axis, as gyro_range (0: unlimited) [m/s^2]
        """
    @acc_range.setter
    def acc_range(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_recovery_time(self) -> float:
        """
        after this long with every accelerometer update rejected, accept again (0: never) [s]
        """
    @acc_recovery_time.setter
    def acc_recovery_time(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_reject(self) -> float:
        """
        reject the accelerometer when ||a|-g| exceeds it (0: off) [m/s^2]
        """
    @acc_reject.setter
    def acc_reject(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_sigma(self) -> float:
        """
        std of each component of the normalized accelerometer [1 (normalized)]
        """
    @acc_sigma.setter
    def acc_sigma(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_tilt_only(self) -> bool:
        """
        the accelerometer corrects the tilt and the horizontal gyro bias only (false: the optimal gain) [-]
        """
    @acc_tilt_only.setter
    def acc_tilt_only(self, arg1: typing.Any) -> None:
        ...
    @property
    def cov_floor(self) -> float:
        """
        eigenvalue floor of the error covariance (0: off) [state units^2]
        """
    @cov_floor.setter
    def cov_floor(self, arg1: typing.Any) -> None:
        ...
    @property
    def declination(self) -> float:
        """
        magnetic declination, east of true north (0: x is magnetic north) [rad]
        """
    @declination.setter
    def declination(self, arg1: typing.Any) -> None:
        ...
    @property
    def gravity(self) -> float:
        """
        magnitude of gravity, in the unit of acc [m/s^2]
        """
    @gravity.setter
    def gravity(self, arg1: typing.Any) -> None:
        ...
    @property
    def gyro_bias_noise(self) -> float:
        """
        gyro-bias random-walk density [rad/s^2/sqrt(Hz)]
        """
    @gyro_bias_noise.setter
    def gyro_bias_noise(self, arg1: typing.Any) -> None:
        ...
    @property
    def gyro_clip(self) -> bool:
        """
        recognize clipped gyro readings (an axis stuck at the largest magnitude seen) and distrust them [-]
        """
    @gyro_clip.setter
    def gyro_clip(self, arg1: typing.Any) -> None:
        ...
    @property
    def gyro_clip_min_rate(self) -> float:
        """
        smallest reading taken for a clip [rad/s]
        """
    @gyro_clip_min_rate.setter
    def gyro_clip_min_rate(self, arg1: typing.Any) -> None:
        ...
    @property
    def gyro_clip_noise(self) -> float:
        """
        std of a clipped step's attitude error about that axis, as a fraction of reading times dt [1]
        """
    @gyro_clip_noise.setter
    def gyro_clip_noise(self, arg1: typing.Any) -> None:
        ...
    @property
    def gyro_clip_repeats(self) -> int:
        """
        a clip: the reading repeats this many previous readings exactly [1]
        """
    @gyro_clip_repeats.setter
    def gyro_clip_repeats(self, arg1: typing.Any) -> None:
        ...
    @property
    def gyro_noise(self) -> float:
        """
        gyro white-noise density (angle random walk) [rad/s/sqrt(Hz)]
        """
    @gyro_noise.setter
    def gyro_noise(self, arg1: typing.Any) -> None:
        ...
    @property
    def gyro_range(self) -> float:
        """
        gyro range per axis: a reading at or above it is saturated and its step skipped (0: unlimited) [rad/s]
        """
    @gyro_range.setter
    def gyro_range(self, arg1: typing.Any) -> None:
        ...
    @property
    def gyro_rate_noise(self) -> float:
        """
        rate-proportional attitude process noise: density gyro_rate_noise * |w - b| (0: off); the attitude filters apply it to the tilt only [1/sqrt(Hz)]
        """
    @gyro_rate_noise.setter
    def gyro_rate_noise(self, arg1: typing.Any) -> None:
        ...
    @property
    def init_att_sigma(self) -> float:
        """
        attitude one-sigma after initialize [rad]
        """
    @init_att_sigma.setter
    def init_att_sigma(self, arg1: typing.Any) -> None:
        ...
    @property
    def init_gyro_bias_sigma(self) -> float:
        """
        gyro-bias one-sigma after initialize [rad/s]
        """
    @init_gyro_bias_sigma.setter
    def init_gyro_bias_sigma(self, arg1: typing.Any) -> None:
        ...
    @property
    def mag_dip_tol(self) -> float:
        """
        reject the magnetometer when its dip differs from the reference by more (0: off) [rad]
        """
    @mag_dip_tol.setter
    def mag_dip_tol(self, arg1: typing.Any) -> None:
        ...
    @property
    def mag_gate(self) -> float:
        """
        NIS gate of the magnetometer update (0: off) [1 (chi-square)]
        """
    @mag_gate.setter
    def mag_gate(self, arg1: typing.Any) -> None:
        ...
    @property
    def mag_heading_only(self) -> bool:
        """
        the magnetometer corrects heading only (false: 3-row update) [-]
        """
    @mag_heading_only.setter
    def mag_heading_only(self, arg1: typing.Any) -> None:
        ...
    @property
    def mag_norm_tol(self) -> float:
        """
        reject the magnetometer when ||m|/m_ref - 1| exceeds it (0: off) [1]
        """
    @mag_norm_tol.setter
    def mag_norm_tol(self, arg1: typing.Any) -> None:
        ...
    @property
    def mag_recovery_time(self) -> float:
        """
        after this long with every sample disturbed, the field becomes the reference (0: never) [s]
        """
    @mag_recovery_time.setter
    def mag_recovery_time(self, arg1: typing.Any) -> None:
        ...
    @property
    def mag_ref_samples(self) -> int:
        """
        magnetometer samples over which the reference dip is averaged [1]
        """
    @mag_ref_samples.setter
    def mag_ref_samples(self, arg1: typing.Any) -> None:
        ...
    @property
    def mag_ref_tau(self) -> float:
        """
        time constant with which the reference norm and dip follow the field [s]
        """
    @mag_ref_tau.setter
    def mag_ref_tau(self, arg1: typing.Any) -> None:
        ...
    @property
    def mag_settle_time(self) -> float:
        """
        after a disturbance, the field must pass the tests this long [s]
        """
    @mag_settle_time.setter
    def mag_settle_time(self, arg1: typing.Any) -> None:
        ...
    @property
    def mag_sigma(self) -> float:
        """
        std of each component of the normalized magnetometer [1 (normalized)]
        """
    @mag_sigma.setter
    def mag_sigma(self, arg1: typing.Any) -> None:
        ...
    @property
    def max_dt(self) -> float:
        """
        longest accepted IMU step [s]
        """
    @max_dt.setter
    def max_dt(self, arg1: typing.Any) -> None:
        ...
    @property
    def rest_acc_th(self) -> float:
        """
        rest: largest deviation of the low-passed accelerometer [m/s^2]
        """
    @rest_acc_th.setter
    def rest_acc_th(self, arg1: typing.Any) -> None:
        ...
    @property
    def rest_detection(self) -> bool:
        """
        detect rest and use it as a zero-rate measurement of the gyro bias [-]
        """
    @rest_detection.setter
    def rest_detection(self, arg1: typing.Any) -> None:
        ...
    @property
    def rest_gyr_th(self) -> float:
        """
        rest: largest deviation of the low-passed gyro [rad/s]
        """
    @rest_gyr_th.setter
    def rest_gyr_th(self, arg1: typing.Any) -> None:
        ...
    @property
    def rest_rate_noise(self) -> float:
        """
        std of the residual rate at rest [rad/s]
        """
    @rest_rate_noise.setter
    def rest_rate_noise(self, arg1: typing.Any) -> None:
        ...
    @property
    def rest_tau(self) -> float:
        """
        rest: low-pass time constant [s]
        """
    @rest_tau.setter
    def rest_tau(self, arg1: typing.Any) -> None:
        ...
    @property
    def rest_time(self) -> float:
        """
        rest: shortest duration [s]
        """
    @rest_time.setter
    def rest_time(self, arg1: typing.Any) -> None:
        ...
class QuaternionEKFPaper_f32:
    @staticmethod
    def state_fields() -> list:
        """
        The state's declaration table: (name, default, unit, doc).
        """
    def __init__(self, params: QuaternionEKFParams_f32) -> None:
        ...
    def get_state(self) -> dict:
        """
        The complete state as a dict of arrays and numbers (set_state restores it exactly).
        """
    def initialize(self, acc: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], mag: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"] | None = None) -> str:
        ...
    def predict(self, gyr: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], dt: typing.SupportsFloat | typing.SupportsIndex) -> str:
        ...
    def reset(self, q_nb: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[4, 1]"], gyro_bias: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], P: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[7, 7]"]) -> str:
        ...
    def run(self, gyr: typing.Annotated[numpy.typing.ArrayLike, numpy.float32], acc: typing.Annotated[numpy.typing.ArrayLike, numpy.float32], mag: typing.Any, dt: typing.Annotated[numpy.typing.ArrayLike, numpy.float32], smooth: bool = False, segment: typing.SupportsInt | typing.SupportsIndex = 256) -> tuple:
        """
        Batch run (GIL released). Returns (quat, bias, sigma, att_sigma, flags); with smooth, a sixth item: the Rauch-Tung-Striebel estimates (quat, bias, sigma, att_sigma) and the smoother's 'info'.
        """
    def set_mag_dip(self, dip: typing.SupportsFloat | typing.SupportsIndex) -> None:
        ...
    def set_state(self, state: dict) -> str:
        """
        Restore a state from get_state(); unknown and missing keys are refused.
        """
    def update_acc(self, acc: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], gate: typing.SupportsFloat | typing.SupportsIndex = 0.0) -> UpdateResult3_f32:
        ...
    def update_acc_mag(self, acc: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], mag: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], gate: typing.SupportsFloat | typing.SupportsIndex = 0.0) -> UpdateResult6_f32:
        ...
    def update_mag(self, mag: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], gate: typing.SupportsFloat | typing.SupportsIndex = 0.0) -> UpdateResult3_f32:
        ...
    @property
    def at_rest(self) -> bool:
        ...
    @property
    def attitude_covariance(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float32], "[3, 3]"]:
        ...
    @property
    def bias(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float32], "[3, 1]"]:
        """
        gyro bias [rad/s]
        """
    @property
    def covariance(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float32], "[7, 7]"]:
        ...
    @property
    def extra_flags(self) -> int:
        ...
    @property
    def initialized(self) -> bool:
        ...
    @property
    def params(self) -> QuaternionEKFParams_f32:
        ...
    @property
    def quat(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float32], "[4, 1]"]:
        """
        q_nb [w, x, y, z]
        """
class QuaternionEKF_f64:
    @staticmethod
    def state_fields() -> list:
        """
        The state's declaration table: (name, default, unit, doc).
        """
    def __init__(self, params: QuaternionEKFParams_f64) -> None:
        ...
    def get_state(self) -> dict:
        """
        The complete state as a dict of arrays and numbers (set_state restores it exactly).
        """
    def initialize(self, acc: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], mag: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"] | None = None) -> str:
        ...
    def predict(self, gyr: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], dt: typing.SupportsFloat | typing.SupportsIndex) -> str:
        ...
    def reset(self, q_nb: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[4, 1]"], gyro_bias: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], P: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[6, 6]"]) -> str:
        ...
    def run(self, gyr: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], acc: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], mag: typing.Any, dt: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], smooth: bool = False, segment: typing.SupportsInt | typing.SupportsIndex = 256) -> tuple:
        """
        Batch run (GIL released). Returns (quat, bias, sigma, att_sigma, flags); with smooth, a sixth item: the Rauch-Tung-Striebel estimates (quat, bias, sigma, att_sigma) and the smoother's 'info'.
        """
    def set_mag_dip(self, dip: typing.SupportsFloat | typing.SupportsIndex) -> None:
        ...
    def set_state(self, state: dict) -> str:
        """
        Restore a state from get_state(); unknown and missing keys are refused.
        """
    def update_acc(self, acc: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], gate: typing.SupportsFloat | typing.SupportsIndex = 0.0) -> UpdateResult3_f64:
        ...
    def update_acc_mag(self, acc: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], mag: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], gate: typing.SupportsFloat | typing.SupportsIndex = 0.0) -> UpdateResult6_f64:
        ...
    def update_mag(self, mag: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], gate: typing.SupportsFloat | typing.SupportsIndex = 0.0) -> UpdateResult3_f64:
        ...
    @property
    def at_rest(self) -> bool:
        ...
    @property
    def attitude_covariance(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[3, 3]"]:
        ...
    @property
    def bias(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[3, 1]"]:
        """
        gyro bias [rad/s]
        """
    @property
    def covariance(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[6, 6]"]:
        ...
    @property
    def extra_flags(self) -> int:
        ...
    @property
    def initialized(self) -> bool:
        ...
    @property
    def params(self) -> QuaternionEKFParams_f64:
        ...
    @property
    def quat(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[4, 1]"]:
        """
        q_nb [w, x, y, z]
        """
class QuaternionEKF_f32:
    @staticmethod
    def state_fields() -> list:
        """
        The state's declaration table: (name, default, unit, doc).
        """
    def __init__(self, params: QuaternionEKFParams_f32) -> None:
        ...
    def get_state(self) -> dict:
        """
        The complete state as a dict of arrays and numbers (set_state restores it exactly).
        """
    def initialize(self, acc: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], mag: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"] | None = None) -> str:
        ...
    def predict(self, gyr: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], dt: typing.SupportsFloat | typing.SupportsIndex) -> str:
        ...
    def reset(self, q_nb: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[4, 1]"], gyro_bias: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], P: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[6, 6]"]) -> str:
        ...
    def run(self, gyr: typing.Annotated[numpy.typing.ArrayLike, numpy.float32], acc: typing.Annotated[numpy.typing.ArrayLike, numpy.float32], mag: typing.Any, dt: typing.Annotated[numpy.typing.ArrayLike, numpy.float32], smooth: bool = False, segment: typing.SupportsInt | typing.SupportsIndex = 256) -> tuple:
        """
        Batch run (GIL released). Returns (quat, bias, sigma, att_sigma, flags); with smooth, a sixth item: the Rauch-Tung-Striebel estimates (quat, bias, sigma, att_sigma) and the smoother's 'info'.
        """
    def set_mag_dip(self, dip: typing.SupportsFloat | typing.SupportsIndex) -> None:
        ...
    def set_state(self, state: dict) -> str:
        """
        Restore a state from get_state(); unknown and missing keys are refused.
        """
    def update_acc(self, acc: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], gate: typing.SupportsFloat | typing.SupportsIndex = 0.0) -> UpdateResult3_f32:
        ...
    def update_acc_mag(self, acc: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], mag: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], gate: typing.SupportsFloat | typing.SupportsIndex = 0.0) -> UpdateResult6_f32:
        ...
    def update_mag(self, mag: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], gate: typing.SupportsFloat | typing.SupportsIndex = 0.0) -> UpdateResult3_f32:
        ...
    @property
    def at_rest(self) -> bool:
        ...
    @property
    def attitude_covariance(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float32], "[3, 3]"]:
        ...
    @property
    def bias(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float32], "[3, 1]"]:
        """
        gyro bias [rad/s]
        """
    @property
    def covariance(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float32], "[6, 6]"]:
        ...
    @property
    def extra_flags(self) -> int:
        ...
    @property
    def initialized(self) -> bool:
        ...
    @property
    def params(self) -> QuaternionEKFParams_f32:
        ...
    @property
    def quat(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float32], "[4, 1]"]:
        """
        q_nb [w, x, y, z]
        """
class EulerEKFParams_f64:
    """
    Parameters of EulerEKF (euler_ekf.hpp).
    """
    @staticmethod
    def fields() -> list:
        """
        The declaration table: a list of (name, default, unit, doc).
        """
    @staticmethod
    def from_dict(d: dict) -> EulerEKFParams_f64:
        """
        From a dict of some fields (the others keep their defaults); unknown keys refused.
        """
    @staticmethod
    def paper() -> EulerEKFParams_f64:
        """
        Parameters of the plain paper-000 baseline (robustness parts off).
        """
    def __init__(self) -> None:
        ...
    def __repr__(self) -> str:
        ...
    def to_dict(self) -> dict:
        ...
    @property
    def acc_adapt(self) -> float:
        """
        adaptive accelerometer noise: std acc_sigma + acc_adapt * ||a|-g|/g [1]
        """
    @acc_adapt.setter
    def acc_adapt(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_bias_dev(self) -> float:
        """
        the accelerometer's weight in the gyro-bias block falls as 1 / (1 + (dev_lp / acc_bias_dev)^2), dev_lp the low-passed ||a|-g| of the raw samples (0: off) [m/s^2]
        """
    @acc_bias_dev.setter
    def acc_bias_dev(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_lp_bias_sigma(self) -> float:
        """
        above this gyro-bias one-sigma the accelerometer low-pass time constant shrinks by (acc_lp_bias_sigma / sigma_b)^2 (0: off) [rad/s]
        """
    @acc_lp_bias_sigma.setter
    def acc_lp_bias_sigma(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_lp_dev(self) -> float:
        """
        the shrink of acc_lp_bias_sigma fades out as the low-passed ||a|-g| of the raw samples approaches this (0: off) [m/s^2]
        """
    @acc_lp_dev.setter
    def acc_lp_dev(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_lp_tau(self) -> float:
        """
        low-pass time constant of the accelerometer in a quasi-inertial frame (0: off) [s]
        """
    @acc_lp_tau.setter
    def acc_lp_tau(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_range(self) -> float:
        """
        accelerometer range per axis, as gyro_range (0: unlimited) [m/s^2]
        """
    @acc_range.setter
    def acc_range(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_recovery_time(self) -> float:
        """
        after this long with every accelerometer update rejected, accept again (0: never) [s]
        """
    @acc_recovery_time.setter
    def acc_recovery_time(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_reject(self) -> float:
        """
        reject the accelerometer when ||a|-g| exceeds it (0: off) [m/s^2]
        """
    @acc_reject.setter
    def acc_reject(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_sigma(self) -> float:
        """
        std of each component of the normalized accelerometer [1 (normalized)]
        """
    @acc_sigma.setter
    def acc_sigma(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_tilt_only(self) -> bool:
        """
        the accelerometer corrects the tilt and the horizontal gyro bias only (false: the optimal gain) [-]
        """
    @acc_tilt_only.setter
    def acc_tilt_only(self, arg1: typing.Any) -> None:
        ...
    @property
    def cov_floor(self) -> float:
        """
        eigenvalue floor of the error covariance (0: off) [state units^2]
        """
    @cov_floor.setter
    def cov_floor(self, arg1: typing.Any) -> None:
        ...
    @property
    def exact_propagation(self) -> bool:
        """
        propagate the angles exactly through the quaternion (false: paper 004 eq. 1's Euler step) [-]
        """
    @exact_propagation.setter
    def exact_propagation(self, arg1: typing.Any) -> None:
        ...
    @property
    def gravity(self) -> float:
        """
        magnitude of gravity, in the unit of acc [m/s^2]
        """
    @gravity.setter
    def gravity(self, arg1: typing.Any) -> None:
        ...
    @property
    def gyro_bias_noise(self) -> float:
        """
        gyro-bias random-walk density [rad/s^2/sqrt(Hz)]
        """
    @gyro_bias_noise.setter
    def gyro_bias_noise(self, arg1: typing.Any) -> None:
        ...
    @property
    def gyro_noise(self) -> float:
        """
        gyro white-noise density (angle random walk) [rad/s/sqrt(Hz)]
        """
    @gyro_noise.setter
    def gyro_noise(self, arg1: typing.Any) -> None:
        ...
    @property
    def gyro_range(self) -> float:
        """
        gyro range per axis: a reading at or above it is saturated and its step skipped (0: unlimited) [rad/s]
        """
    @gyro_range.setter
    def gyro_range(self, arg1: typing.Any) -> None:
        ...
    @property
    def init_att_sigma(self) -> float:
        """
        one-sigma of each Euler angle after initialize [rad]
        """
    @init_att_sigma.setter
    def init_att_sigma(self, arg1: typing.Any) -> None:
        ...
    @property
    def init_gyro_bias_sigma(self) -> float:
        """
        gyro-bias one-sigma after initialize [rad/s]
        """
    @init_gyro_bias_sigma.setter
    def init_gyro_bias_sigma(self, arg1: typing.Any) -> None:
        ...
    @property
    def mag_dip_tol(self) -> float:
        """
        reject the magnetometer when its dip differs from the reference by more (0: off) [rad]
        """
    @mag_dip_tol.setter
    def mag_dip_tol(self, arg1: typing.Any) -> None:
        ...
    @property
    def mag_norm_tol(self) -> float:
        """
        reject the magnetometer when ||m|/m_ref - 1| exceeds it (0: off) [1]
        """
    @mag_norm_tol.setter
    def mag_norm_tol(self, arg1: typing.Any) -> None:
        ...
    @property
    def mag_recovery_time(self) -> float:
        """
        after this long with every sample disturbed, the field becomes the reference (0: never) [s]
        """
    @mag_recovery_time.setter
    def mag_recovery_time(self, arg1: typing.Any) -> None:
        ...
    @property
    def mag_ref_samples(self) -> int:
        """
        magnetometer samples over which the reference dip is averaged [1]
        """
    @mag_ref_samples.setter
    def mag_ref_samples(self, arg1: typing.Any) -> None:
        ...
    @property
    def mag_ref_tau(self) -> float:
        """
        time constant with which the reference norm and dip follow the field [s]
        """
    @mag_ref_tau.setter
    def mag_ref_tau(self, arg1: typing.Any) -> None:
        ...
    @property
    def mag_settle_time(self) -> float:
        """
        after a disturbance, the field must pass the tests this long [s]
        """
    @mag_settle_time.setter
    def mag_settle_time(self, arg1: typing.Any) -> None:
        ...
    @property
    def mag_sigma(self) -> float:
        """
        std of each component of the normalized magnetometer [1 (normalized)]
        """
    @mag_sigma.setter
    def mag_sigma(self, arg1: typing.Any) -> None:
        ...
    @property
    def max_dt(self) -> float:
        """
        longest accepted IMU step [s]
        """
    @max_dt.setter
    def max_dt(self, arg1: typing.Any) -> None:
        ...
    @property
    def rest_acc_th(self) -> float:
        """
        rest: largest deviation of the low-passed accelerometer [m/s^2]
        """
    @rest_acc_th.setter
    def rest_acc_th(self, arg1: typing.Any) -> None:
        ...
    @property
    def rest_detection(self) -> bool:
        """
        detect rest and use it as a zero-rate measurement of the gyro bias [-]
        """
    @rest_detection.setter
    def rest_detection(self, arg1: typing.Any) -> None:
        ...
    @property
    def rest_gyr_th(self) -> float:
        """
        rest: largest deviation of the low-passed gyro [rad/s]
        """
    @rest_gyr_th.setter
    def rest_gyr_th(self, arg1: typing.Any) -> None:
        ...
    @property
    def rest_rate_noise(self) -> float:
        """
        std of the residual rate at rest [rad/s]
        """
    @rest_rate_noise.setter
    def rest_rate_noise(self, arg1: typing.Any) -> None:
        ...
    @property
    def rest_tau(self) -> float:
        """
        rest: low-pass time constant [s]
        """
    @rest_tau.setter
    def rest_tau(self, arg1: typing.Any) -> None:
        ...
    @property
    def rest_time(self) -> float:
        """
        rest: shortest duration [s]
        """
    @rest_time.setter
    def rest_time(self, arg1: typing.Any) -> None:
        ...
    @property
    def singular_cos(self) -> float:
        """
        the Euler parametrization is flagged singular where abs(cos(pitch)) is below it [1]
        """
    @singular_cos.setter
    def singular_cos(self, arg1: typing.Any) -> None:
        ...
class EulerEKF_f64:
    @staticmethod
    def state_fields() -> list:
        """
        The state's declaration table: (name, default, unit, doc).
        """
    def __init__(self, params: EulerEKFParams_f64) -> None:
        ...
    def get_state(self) -> dict:
        """
        The complete state as a dict of arrays and numbers (set_state restores it exactly).
        """
    def initialize(self, acc: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], mag: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"] | None = None) -> str:
        ...
    def predict(self, gyr: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], dt: typing.SupportsFloat | typing.SupportsIndex) -> str:
        ...
    def reset(self, euler: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], gyro_bias: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], P: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[6, 6]"]) -> str:
        ...
    def run(self, gyr: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], acc: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], mag: typing.Any, dt: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], smooth: bool = False, segment: typing.SupportsInt | typing.SupportsIndex = 256) -> tuple:
        """
        Batch run (GIL released). Returns (quat, bias, sigma, att_sigma, flags); with smooth, a sixth item: the Rauch-Tung-Striebel estimates (quat, bias, sigma, att_sigma) and the smoother's 'info'.
        """
    def set_mag_dip(self, dip: typing.SupportsFloat | typing.SupportsIndex) -> None:
        ...
    def set_state(self, state: dict) -> str:
        """
        Restore a state from get_state(); unknown and missing keys are refused.
        """
    def update_acc(self, acc: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], gate: typing.SupportsFloat | typing.SupportsIndex = 0.0) -> UpdateResult3_f64:
        ...
    def update_mag(self, mag: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], gate: typing.SupportsFloat | typing.SupportsIndex = 0.0) -> UpdateResult3_f64:
        ...
    @property
    def at_rest(self) -> bool:
        ...
    @property
    def attitude_covariance(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[3, 3]"]:
        ...
    @property
    def bias(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[3, 1]"]:
        """
        gyro bias [rad/s]
        """
    @property
    def covariance(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[6, 6]"]:
        ...
    @property
    def euler(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[3, 1]"]:
        ...
    @property
    def extra_flags(self) -> int:
        ...
    @property
    def initialized(self) -> bool:
        ...
    @property
    def near_singularity(self) -> bool:
        ...
    @property
    def params(self) -> EulerEKFParams_f64:
        ...
    @property
    def quat(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[4, 1]"]:
        """
        q_nb [w, x, y, z]
        """
class EulerEKFParams_f32:
    """
    Parameters of EulerEKF (euler_ekf.hpp).
    """
    @staticmethod
    def fields() -> list:
        """
        The declaration table: a list of (name, default, unit, doc).
        """
    @staticmethod
    def from_dict(d: dict) -> EulerEKFParams_f32:
        """
        From a dict of some fields (the others keep their defaults); unknown keys refused.
        """
    @staticmethod
    def paper() -> EulerEKFParams_f32:
        """
        Parameters of the plain paper-000 baseline (robustness parts off).
        """
    def __init__(self) -> None:
        ...
    def __repr__(self) -> str:
        ...
    def to_dict(self) -> dict:
        ...
    @property
    def acc_adapt(self) -> float:
        """
        adaptive accelerometer noise: std acc_sigma + acc_adapt * ||a|-g|/g [1]
        """
    @acc_adapt.setter
    def acc_adapt(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_bias_dev(self) -> float:
        """
        the accelerometer's weight in the gyro-bias block falls as 1 / (1 + (dev_lp / acc_bias_dev)^2), dev_lp the low-passed ||a|-g| of the raw samples (0: off) [m/s^2]
        """
    @acc_bias_dev.setter
    def acc_bias_dev(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_lp_bias_sigma(self) -> float:
        """
        above this gyro-bias one-sigma the accelerometer low-pass time constant shrinks by (acc_lp_bias_sigma / sigma_b)^2 (0: off) [rad/s]
        """
    @acc_lp_bias_sigma.setter
    def acc_lp_bias_sigma(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_lp_dev(self) -> float:
        """
        the shrink of acc_lp_bias_sigma fades out as the low-passed ||a|-g| of the raw samples approaches this (0: off) [m/s^2]
        """
    @acc_lp_dev.setter
    def acc_lp_dev(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_lp_tau(self) -> float:
        """
        low-pass time constant of the accelerometer in a quasi-inertial frame (0: off) [s]
        """
    @acc_lp_tau.setter
    def acc_lp_tau(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_range(self) -> float:
        """
        accelerometer range per axis, as gyro_range (0: unlimited) [m/s^2]
        """
    @acc_range.setter
    def acc_range(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_recovery_time(self) -> float:
        """
        after this long with every accelerometer update rejected, accept again (0: never) [s]
        """
    @acc_recovery_time.setter
    def acc_recovery_time(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_reject(self) -> float:
        """
        reject the accelerometer when ||a|-g| exceeds it (0: off) [m/s^2]
        """
    @acc_reject.setter
    def acc_reject(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_sigma(self) -> float:
        """
        std of each component of the normalized accelerometer [1 (normalized)]
        """
    @acc_sigma.setter
    def acc_sigma(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_tilt_only(self) -> bool:
        """
        the accelerometer corrects the tilt and the horizontal gyro bias only (false: the optimal gain) [-]
        """
    @acc_tilt_only.setter
    def acc_tilt_only(self, arg1: typing.Any) -> None:
        ...
    @property
    def cov_floor(self) -> float:
        """
        eigenvalue floor of the error covariance (0: off) [state units^2]
        """
    @cov_floor.setter
    def cov_floor(self, arg1: typing.Any) -> None:
        ...
    @property
    def exact_propagation(self) -> bool:
        """
        propagate the angles exactly through the quaternion (false: paper 004 eq. 1's Euler step) [-]
        """
    @exact_propagation.setter
    def exact_propagation(self, arg1: typing.Any) -> None:
        ...
    @property
    def gravity(self) -> float:
        """
        magnitude of gravity, in the unit of acc [m/s^2]
        """
    @gravity.setter
    def gravity(self, arg1: typing.Any) -> None:
        ...
    @property
    def gyro_bias_noise(self) -> float:
        """
        gyro-bias random-walk density [rad/s^2/sqrt(Hz)]
        """
    @gyro_bias_noise.setter
    def gyro_bias_noise(self, arg1: typing.Any) -> None:
        ...
    @property
    def gyro_noise(self) -> float:
        """
        gyro white-noise density (angle random walk) [rad/s/sqrt(Hz)]
        """
    @gyro_noise.setter
    def gyro_noise(self, arg1: typing.Any) -> None:
        ...
    @property
    def gyro_range(self) -> float:
        """
        gyro range per axis: a reading at or above it is saturated and its step skipped (0: unlimited) [rad/s]
        """
    @gyro_range.setter
    def gyro_range(self, arg1: typing.Any) -> None:
        ...
    @property
    def init_att_sigma(self) -> float:
        """
        one-sigma of each Euler angle after initialize [rad]
        """
    @init_att_sigma.setter
    def init_att_sigma(self, arg1: typing.Any) -> None:
        ...
    @property
    def init_gyro_bias_sigma(self) -> float:
        """
        gyro-bias one-sigma after initialize [rad/s]
        """
    @init_gyro_bias_sigma.setter
    def init_gyro_bias_sigma(self, arg1: typing.Any) -> None:
        ...
    @property
    def mag_dip_tol(self) -> float:
        """
        reject the magnetometer when its dip differs from the reference by more (0: off) [rad]
        """
    @mag_dip_tol.setter
    def mag_dip_tol(self, arg1: typing.Any) -> None:
        ...
    @property
    def mag_norm_tol(self) -> float:
        """
        reject the magnetometer when ||m|/m_ref - 1| exceeds it (0: off) [1]
        """
    @mag_norm_tol.setter
    def mag_norm_tol(self, arg1: typing.Any) -> None:
        ...
    @property
    def mag_recovery_time(self) -> float:
        """
        after this long with every sample disturbed, the field becomes the reference (0: never) [s]
        """
    @mag_recovery_time.setter
    def mag_recovery_time(self, arg1: typing.Any) -> None:
        ...
    @property
    def mag_ref_samples(self) -> int:
        """
        magnetometer samples over which the reference dip is averaged [1]
        """
    @mag_ref_samples.setter
    def mag_ref_samples(self, arg1: typing.Any) -> None:
        ...
    @property
    def mag_ref_tau(self) -> float:
        """
        time constant with which the reference norm and dip follow the field [s]
        """
    @mag_ref_tau.setter
    def mag_ref_tau(self, arg1: typing.Any) -> None:
        ...
    @property
    def mag_settle_time(self) -> float:
        """
        after a disturbance, the field must pass the tests this long [s]
        """
    @mag_settle_time.setter
    def mag_settle_time(self, arg1: typing.Any) -> None:
        ...
    @property
    def mag_sigma(self) -> float:
        """
        std of each component of the normalized magnetometer [1 (normalized)]
        """
    @mag_sigma.setter
    def mag_sigma(self, arg1: typing.Any) -> None:
        ...
    @property
    def max_dt(self) -> float:
        """
        longest accepted IMU step [s]
        """
    @max_dt.setter
    def max_dt(self, arg1: typing.Any) -> None:
        ...
    @property
    def rest_acc_th(self) -> float:
        """
        rest: largest deviation of the low-passed accelerometer [m/s^2]
        """
    @rest_acc_th.setter
    def rest_acc_th(self, arg1: typing.Any) -> None:
        ...
    @property
    def rest_detection(self) -> bool:
        """
        detect rest and use it as a zero-rate measurement of the gyro bias [-]
        """
    @rest_detection.setter
    def rest_detection(self, arg1: typing.Any) -> None:
        ...
    @property
    def rest_gyr_th(self) -> float:
        """
        rest: largest deviation of the low-passed gyro [rad/s]
        """
    @rest_gyr_th.setter
    def rest_gyr_th(self, arg1: typing.Any) -> None:
        ...
    @property
    def rest_rate_noise(self) -> float:
        """
        std of the residual rate at rest [rad/s]
        """
    @rest_rate_noise.setter
    def rest_rate_noise(self, arg1: typing.Any) -> None:
        ...
    @property
    def rest_tau(self) -> float:
        """
        rest: low-pass time constant [s]
        """
    @rest_tau.setter
    def rest_tau(self, arg1: typing.Any) -> None:
        ...
    @property
    def rest_time(self) -> float:
        """
        rest: shortest duration [s]
        """
    @rest_time.setter
    def rest_time(self, arg1: typing.Any) -> None:
        ...
    @property
    def singular_cos(self) -> float:
        """
        the Euler parametrization is flagged singular where abs(cos(pitch)) is below it [1]
        """
    @singular_cos.setter
    def singular_cos(self, arg1: typing.Any) -> None:
        ...
class EulerEKF_f32:
    @staticmethod
    def state_fields() -> list:
        """
        The state's declaration table: (name, default, unit, doc).
        """
    def __init__(self, params: EulerEKFParams_f32) -> None:
        ...
    def get_state(self) -> dict:
        """
        The complete state as a dict of arrays and numbers (set_state restores it exactly).
        """
    def initialize(self, acc: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], mag: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"] | None = None) -> str:
        ...
    def predict(self, gyr: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], dt: typing.SupportsFloat | typing.SupportsIndex) -> str:
        ...
    def reset(self, euler: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], gyro_bias: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], P: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[6, 6]"]) -> str:
        ...
    def run(self, gyr: typing.Annotated[numpy.typing.ArrayLike, numpy.float32], acc: typing.Annotated[numpy.typing.ArrayLike, numpy.float32], mag: typing.Any, dt: typing.Annotated[numpy.typing.ArrayLike, numpy.float32], smooth: bool = False, segment: typing.SupportsInt | typing.SupportsIndex = 256) -> tuple:
        """
        Batch run (GIL released). Returns (quat, bias, sigma, att_sigma, flags); with smooth, a sixth item: the Rauch-Tung-Striebel estimates (quat, bias, sigma, att_sigma) and the smoother's 'info'.
        """
    def set_mag_dip(self, dip: typing.SupportsFloat | typing.SupportsIndex) -> None:
        ...
    def set_state(self, state: dict) -> str:
        """
        Restore a state from get_state(); unknown and missing keys are refused.
        """
    def update_acc(self, acc: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], gate: typing.SupportsFloat | typing.SupportsIndex = 0.0) -> UpdateResult3_f32:
        ...
    def update_mag(self, mag: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], gate: typing.SupportsFloat | typing.SupportsIndex = 0.0) -> UpdateResult3_f32:
        ...
    @property
    def at_rest(self) -> bool:
        ...
    @property
    def attitude_covariance(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float32], "[3, 3]"]:
        ...
    @property
    def bias(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float32], "[3, 1]"]:
        """
        gyro bias [rad/s]
        """
    @property
    def covariance(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float32], "[6, 6]"]:
        ...
    @property
    def euler(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float32], "[3, 1]"]:
        ...
    @property
    def extra_flags(self) -> int:
        ...
    @property
    def initialized(self) -> bool:
        ...
    @property
    def near_singularity(self) -> bool:
        ...
    @property
    def params(self) -> EulerEKFParams_f32:
        ...
    @property
    def quat(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float32], "[4, 1]"]:
        """
        q_nb [w, x, y, z]
        """
class MargUpdateResult_f64:
    """
    Outcome of one Gauss-Newton update.
    """
    def __repr__(self) -> str:
        ...
    @property
    def accepted(self) -> bool:
        ...
    @property
    def converged(self) -> bool:
        ...
    @property
    def correction(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[3, 1]"]:
        ...
    @property
    def gps_corrected(self) -> bool:
        ...
    @property
    def iterations(self) -> int:
        ...
    @property
    def residual(self) -> float:
        ...
    @property
    def residual_final(self) -> float:
        ...
    @property
    def status(self) -> str:
        ...
class MargFilterParams_f64:
    """
    Parameters of MargFilter (marg_filter.hpp).
    """
    @staticmethod
    def fields() -> list:
        """
        The declaration table: a list of (name, default, unit, doc).
        """
    @staticmethod
    def from_dict(d: dict) -> MargFilterParams_f64:
        """
        From a dict of some fields (the others keep their defaults); unknown keys refused.
        """
    @staticmethod
    def paper() -> MargFilterParams_f64:
        """
        Parameters of the plain paper-001 filter (robustness parts off).
        """
    def __init__(self) -> None:
        ...
    def __repr__(self) -> str:
        ...
    def to_dict(self) -> dict:
        ...
    @property
    def acc_adapt(self) -> float:
        """
        adaptive accelerometer noise: std acc_sigma + acc_adapt * ||a|-g|/g [1]
        """
    @acc_adapt.setter
    def acc_adapt(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_bias_dev(self) -> float:
        """
        the accelerometer's weight in the gyro-bias block falls as 1 / (1 + (dev_lp / acc_bias_dev)^2), dev_lp the low-passed ||a|-g| of the raw samples (0: off) [m/s^2]
        """
    @acc_bias_dev.setter
    def acc_bias_dev(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_lp_bias_sigma(self) -> float:
        """
        above this gyro-bias one-sigma the accelerometer low-pass time constant shrinks by (acc_lp_bias_sigma / sigma_b)^2 (0: off) [rad/s]
        """
    @acc_lp_bias_sigma.setter
    def acc_lp_bias_sigma(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_lp_dev(self) -> float:
        """
        the shrink of acc_lp_bias_sigma fades out as the low-passed ||a|-g| of the raw samples approaches this (0: off) [m/s^2]
        """
    @acc_lp_dev.setter
    def acc_lp_dev(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_lp_tau(self) -> float:
        """
        low-pass time constant of the accelerometer in a quasi-inertial frame (0: off) [s]
        """
    @acc_lp_tau.setter
    def acc_lp_tau(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_recovery_time(self) -> float:
        """
        after this long with every accelerometer update rejected, accept again (0: never) [s]
        """
    @acc_recovery_time.setter
    def acc_recovery_time(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_reject(self) -> float:
        """
        reject the accelerometer when ||a|-g| exceeds it (0: off) [m/s^2]
        """
    @acc_reject.setter
    def acc_reject(self, arg1: typing.Any) -> None:
        ...
    @property
    def bias_gain(self) -> float:
        """
        gyro-bias integral gain (0: no bias estimate) [1/s^2]
        """
    @bias_gain.setter
    def bias_gain(self, arg1: typing.Any) -> None:
        ...
    @property
    def declination(self) -> float:
        """
        magnetic declination, east of true north (GPS velocities are rotated into the magnetic frame) [rad]
        """
    @declination.setter
    def declination(self, arg1: typing.Any) -> None:
        ...
    @property
    def gain(self) -> float:
        """
        k of eq. (6): pull towards the Gauss-Newton attitude (0: gyro only) [1/s]
        """
    @gain.setter
    def gain(self, arg1: typing.Any) -> None:
        ...
    @property
    def gn_max_iter(self) -> int:
        """
        Gauss-Newton iterations per update, at most [1]
        """
    @gn_max_iter.setter
    def gn_max_iter(self, arg1: typing.Any) -> None:
        ...
    @property
    def gn_tol(self) -> float:
        """
        the iteration stops when |dq| is below it [1]
        """
    @gn_tol.setter
    def gn_tol(self, arg1: typing.Any) -> None:
        ...
    @property
    def gps_acc_tau(self) -> float:
        """
        low-pass time constant of the GPS acceleration [s]
        """
    @gps_acc_tau.setter
    def gps_acc_tau(self, arg1: typing.Any) -> None:
        ...
    @property
    def gps_correction(self) -> bool:
        """
        apply eq. (7) when a GPS acceleration is available [-]
        """
    @gps_correction.setter
    def gps_correction(self, arg1: typing.Any) -> None:
        ...
    @property
    def gps_timeout(self) -> float:
        """
        a GPS acceleration older than this is not used [s]
        """
    @gps_timeout.setter
    def gps_timeout(self, arg1: typing.Any) -> None:
        ...
    @property
    def gravity(self) -> float:
        """
        magnitude of gravity, in the unit of acc [m/s^2]
        """
    @gravity.setter
    def gravity(self, arg1: typing.Any) -> None:
        ...
    @property
    def lever_arm_b(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[3, 1]"]:
        """
        GPS antenna relative to the IMU, body FRD [m]
        """
    @lever_arm_b.setter
    def lever_arm_b(self, arg1: typing.Any) -> None:
        ...
    @property
    def mag_dip_tol(self) -> float:
        """
        reject the magnetometer when its dip differs from the reference by more (0: off) [rad]
        """
    @mag_dip_tol.setter
    def mag_dip_tol(self, arg1: typing.Any) -> None:
        ...
    @property
    def mag_norm_tol(self) -> float:
        """
        reject the magnetometer when ||m|/m_ref - 1| exceeds it (0: off) [1]
        """
    @mag_norm_tol.setter
    def mag_norm_tol(self, arg1: typing.Any) -> None:
        ...
    @property
    def mag_recovery_time(self) -> float:
        """
        after this long with every sample disturbed, the field becomes the reference (0: never) [s]
        """
    @mag_recovery_time.setter
    def mag_recovery_time(self, arg1: typing.Any) -> None:
        ...
    @property
    def mag_ref_samples(self) -> int:
        """
        magnetometer samples over which the reference dip is averaged [1]
        """
    @mag_ref_samples.setter
    def mag_ref_samples(self, arg1: typing.Any) -> None:
        ...
    @property
    def mag_ref_tau(self) -> float:
        """
        time constant with which the reference norm and dip follow the field [s]
        """
    @mag_ref_tau.setter
    def mag_ref_tau(self, arg1: typing.Any) -> None:
        ...
    @property
    def mag_settle_time(self) -> float:
        """
        after a disturbance, the field must pass the tests this long [s]
        """
    @mag_settle_time.setter
    def mag_settle_time(self, arg1: typing.Any) -> None:
        ...
    @property
    def max_dt(self) -> float:
        """
        longest accepted IMU step [s]
        """
    @max_dt.setter
    def max_dt(self, arg1: typing.Any) -> None:
        ...
    @property
    def omega_dot_tau(self) -> float:
        """
        low-pass time constant of the angular acceleration [s]
        """
    @omega_dot_tau.setter
    def omega_dot_tau(self, arg1: typing.Any) -> None:
        ...
    @property
    def rest_acc_th(self) -> float:
        """
        rest: largest deviation of the low-passed accelerometer [m/s^2]
        """
    @rest_acc_th.setter
    def rest_acc_th(self, arg1: typing.Any) -> None:
        ...
    @property
    def rest_detection(self) -> bool:
        """
        detect rest and use it as a zero-rate measurement of the gyro bias [-]
        """
    @rest_detection.setter
    def rest_detection(self, arg1: typing.Any) -> None:
        ...
    @property
    def rest_gyr_th(self) -> float:
        """
        rest: largest deviation of the low-passed gyro [rad/s]
        """
    @rest_gyr_th.setter
    def rest_gyr_th(self, arg1: typing.Any) -> None:
        ...
    @property
    def rest_rate_noise(self) -> float:
        """
        std of the residual rate at rest [rad/s]
        """
    @rest_rate_noise.setter
    def rest_rate_noise(self, arg1: typing.Any) -> None:
        ...
    @property
    def rest_tau(self) -> float:
        """
        rest: low-pass time constant [s]
        """
    @rest_tau.setter
    def rest_tau(self, arg1: typing.Any) -> None:
        ...
    @property
    def rest_time(self) -> float:
        """
        rest: shortest duration [s]
        """
    @rest_time.setter
    def rest_time(self, arg1: typing.Any) -> None:
        ...
    @property
    def valid(self) -> bool:
        ...
class MargFilter_f64:
    @staticmethod
    def state_fields() -> list:
        """
        The state's declaration table: (name, default, unit, doc).
        """
    def __init__(self, params: MargFilterParams_f64) -> None:
        ...
    def get_state(self) -> dict:
        """
        The complete state as a dict of arrays and numbers (set_state restores it exactly).
        """
    def initialize(self, acc: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], mag: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"] | None = None) -> str:
        ...
    def predict(self, gyr: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], dt: typing.SupportsFloat | typing.SupportsIndex) -> str:
        ...
    def reset(self, q_nb: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[4, 1]"], gyro_bias: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"]) -> str:
        ...
    def run(self, t: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], dt: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], gyr: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], acc: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], mag: typing.Any, gps_t: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], gps_vel_n: typing.Annotated[numpy.typing.ArrayLike, numpy.float64]) -> tuple:
        """
        Batch run (GIL released). Returns (quat, bias, gps_acc_n, residual, flags).
        """
    def set_mag_dip(self, dip: typing.SupportsFloat | typing.SupportsIndex) -> None:
        ...
    def set_state(self, state: dict) -> str:
        """
        Restore a state from get_state(); unknown and missing keys are refused.
        """
    def update_acc(self, acc: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"]) -> MargUpdateResult_f64:
        ...
    def update_acc_mag(self, acc: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], mag: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"]) -> MargUpdateResult_f64:
        ...
    def update_gps_velocity(self, v_n: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], t: typing.SupportsFloat | typing.SupportsIndex) -> str:
        ...
    @property
    def at_rest(self) -> bool:
        ...
    @property
    def bias(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[3, 1]"]:
        """
        gyro bias [rad/s]
        """
    @property
    def gps_acc_available(self) -> bool:
        ...
    @property
    def gps_acc_n(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[3, 1]"]:
        ...
    @property
    def initialized(self) -> bool:
        ...
    @property
    def params(self) -> MargFilterParams_f64:
        ...
    @property
    def quat(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[4, 1]"]:
        """
        q_nb [w, x, y, z]
        """
class MargUpdateResult_f32:
    """
    Outcome of one Gauss-Newton update.
    """
    def __repr__(self) -> str:
        ...
    @property
    def accepted(self) -> bool:
        ...
    @property
    def converged(self) -> bool:
        ...
    @property
    def correction(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float32], "[3, 1]"]:
        ...
    @property
    def gps_corrected(self) -> bool:
        ...
    @property
    def iterations(self) -> int:
        ...
    @property
    def residual(self) -> float:
        ...
    @property
    def residual_final(self) -> float:
        ...
    @property
    def status(self) -> str:
        ...
class MargFilterParams_f32:
    """
    Parameters of MargFilter (marg_filter.hpp).
    """
    @staticmethod
    def fields() -> list:
        """
        The declaration table: a list of (name, default, unit, doc).
        """
    @staticmethod
    def from_dict(d: dict) -> MargFilterParams_f32:
        """
        From a dict of some fields (the others keep their defaults); unknown keys refused.
        """
    @staticmethod
    def paper() -> MargFilterParams_f32:
        """
        Parameters of the plain paper-001 filter (robustness parts off).
        """
    def __init__(self) -> None:
        ...
    def __repr__(self) -> str:
        ...
    def to_dict(self) -> dict:
        ...
    @property
    def acc_adapt(self) -> float:
        """
        adaptive accelerometer noise: std acc_sigma + acc_adapt * ||a|-g|/g [1]
        """
    @acc_adapt.setter
    def acc_adapt(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_bias_dev(self) -> float:
        """
        the accelerometer's weight in the gyro-bias block falls as 1 / (1 + (dev_lp / acc_bias_dev)^2), dev_lp the low-passed ||a|-g| of the raw samples (0: off) [m/s^2]
        """
    @acc_bias_dev.setter
    def acc_bias_dev(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_lp_bias_sigma(self) -> float:
        """
        above this gyro-bias one-sigma the accelerometer low-pass time constant shrinks by (acc_lp_bias_sigma / sigma_b)^2 (0: off) [rad/s]
        """
    @acc_lp_bias_sigma.setter
    def acc_lp_bias_sigma(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_lp_dev(self) -> float:
        """
        the shrink of acc_lp_bias_sigma fades out as the low-passed ||a|-g| of the raw samples approaches this (0: off) [m/s^2]
        """
    @acc_lp_dev.setter
    def acc_lp_dev(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_lp_tau(self) -> float:
        """
        low-pass time constant of the accelerometer in a quasi-inertial frame (0: off) [s]
        """
    @acc_lp_tau.setter
    def acc_lp_tau(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_recovery_time(self) -> float:
        """
        after this long with every accelerometer update rejected, accept again (0: never) [s]
        """
    @acc_recovery_time.setter
    def acc_recovery_time(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_reject(self) -> float:
        """
        reject the accelerometer when ||a|-g| exceeds it (0: off) [m/s^2]
        """
    @acc_reject.setter
    def acc_reject(self, arg1: typing.Any) -> None:
        ...
    @property
    def bias_gain(self) -> float:
        """
        gyro-bias integral gain (0: no bias estimate) [1/s^2]
        """
    @bias_gain.setter
    def bias_gain(self, arg1: typing.Any) -> None:
        ...
    @property
    def declination(self) -> float:
        """
        magnetic declination, east of true north (GPS velocities are rotated into the magnetic frame) [rad]
        """
    @declination.setter
    def declination(self, arg1: typing.Any) -> None:
        ...
    @property
    def gain(self) -> float:
        """
        k of eq. (6): pull towards the Gauss-Newton attitude (0: gyro only) [1/s]
        """
    @gain.setter
    def gain(self, arg1: typing.Any) -> None:
        ...
    @property
    def gn_max_iter(self) -> int:
        """
        Gauss-Newton iterations per update, at most [1]
        """
    @gn_max_iter.setter
    def gn_max_iter(self, arg1: typing.Any) -> None:
        ...
    @property
    def gn_tol(self) -> float:
        """
        the iteration stops when |dq| is below it [1]
        """
    @gn_tol.setter
    def gn_tol(self, arg1: typing.Any) -> None:
        ...
    @property
    def gps_acc_tau(self) -> float:
        """
        low-pass time constant of the GPS acceleration [s]
        """
    @gps_acc_tau.setter
    def gps_acc_tau(self, arg1: typing.Any) -> None:
        ...
    @property
    def gps_correction(self) -> bool:
        """
        apply eq. (7) when a GPS acceleration is available [-]
        """
    @gps_correction.setter
    def gps_correction(self, arg1: typing.Any) -> None:
        ...
    @property
    def gps_timeout(self) -> float:
        """
        a GPS acceleration older than this is not used [s]
        """
    @gps_timeout.setter
    def gps_timeout(self, arg1: typing.Any) -> None:
        ...
    @property
    def gravity(self) -> float:
        """
        magnitude of gravity, in the unit of acc [m/s^2]
        """
    @gravity.setter
    def gravity(self, arg1: typing.Any) -> None:
        ...
    @property
    def lever_arm_b(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float32], "[3, 1]"]:
        """
        GPS antenna relative to the IMU, body FRD [m]
        """
    @lever_arm_b.setter
    def lever_arm_b(self, arg1: typing.Any) -> None:
        ...
    @property
    def mag_dip_tol(self) -> float:
        """
        reject the magnetometer when its dip differs from the reference by more (0: off) [rad]
        """
    @mag_dip_tol.setter
    def mag_dip_tol(self, arg1: typing.Any) -> None:
        ...
    @property
    def mag_norm_tol(self) -> float:
        """
        reject the magnetometer when ||m|/m_ref - 1| exceeds it (0: off) [1]
        """
    @mag_norm_tol.setter
    def mag_norm_tol(self, arg1: typing.Any) -> None:
        ...
    @property
    def mag_recovery_time(self) -> float:
        """
        after this long with every sample disturbed, the field becomes the reference (0: never) [s]
        """
    @mag_recovery_time.setter
    def mag_recovery_time(self, arg1: typing.Any) -> None:
        ...
    @property
    def mag_ref_samples(self) -> int:
        """
        magnetometer samples over which the reference dip is averaged [1]
        """
    @mag_ref_samples.setter
    def mag_ref_samples(self, arg1: typing.Any) -> None:
        ...
    @property
    def mag_ref_tau(self) -> float:
        """
        time constant with which the reference norm and dip follow the field [s]
        """
    @mag_ref_tau.setter
    def mag_ref_tau(self, arg1: typing.Any) -> None:
        ...
    @property
    def mag_settle_time(self) -> float:
        """
        after a disturbance, the field must pass the tests this long [s]
        """
    @mag_settle_time.setter
    def mag_settle_time(self, arg1: typing.Any) -> None:
        ...
    @property
    def max_dt(self) -> float:
        """
        longest accepted IMU step [s]
        """
    @max_dt.setter
    def max_dt(self, arg1: typing.Any) -> None:
        ...
    @property
    def omega_dot_tau(self) -> float:
        """
        low-pass time constant of the angular acceleration [s]
        """
    @omega_dot_tau.setter
    def omega_dot_tau(self, arg1: typing.Any) -> None:
        ...
    @property
    def rest_acc_th(self) -> float:
        """
        rest: largest deviation of the low-passed accelerometer [m/s^2]
        """
    @rest_acc_th.setter
    def rest_acc_th(self, arg1: typing.Any) -> None:
        ...
    @property
    def rest_detection(self) -> bool:
        """
        detect rest and use it as a zero-rate measurement of the gyro bias [-]
        """
    @rest_detection.setter
    def rest_detection(self, arg1: typing.Any) -> None:
        ...
    @property
    def rest_gyr_th(self) -> float:
        """
        rest: largest deviation of the low-passed gyro [rad/s]
        """
    @rest_gyr_th.setter
    def rest_gyr_th(self, arg1: typing.Any) -> None:
        ...
    @property
    def rest_rate_noise(self) -> float:
        """
        std of the residual rate at rest [rad/s]
        """
    @rest_rate_noise.setter
    def rest_rate_noise(self, arg1: typing.Any) -> None:
        ...
    @property
    def rest_tau(self) -> float:
        """
        rest: low-pass time constant [s]
        """
    @rest_tau.setter
    def rest_tau(self, arg1: typing.Any) -> None:
        ...
    @property
    def rest_time(self) -> float:
        """
        rest: shortest duration [s]
        """
    @rest_time.setter
    def rest_time(self, arg1: typing.Any) -> None:
        ...
    @property
    def valid(self) -> bool:
        ...
class MargFilter_f32:
    @staticmethod
    def state_fields() -> list:
        """
        The state's declaration table: (name, default, unit, doc).
        """
    def __init__(self, params: MargFilterParams_f32) -> None:
        ...
    def get_state(self) -> dict:
        """
        The complete state as a dict of arrays and numbers (set_state restores it exactly).
        """
    def initialize(self, acc: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], mag: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"] | None = None) -> str:
        ...
    def predict(self, gyr: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], dt: typing.SupportsFloat | typing.SupportsIndex) -> str:
        ...
    def reset(self, q_nb: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[4, 1]"], gyro_bias: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"]) -> str:
        ...
    def run(self, t: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], dt: typing.Annotated[numpy.typing.ArrayLike, numpy.float32], gyr: typing.Annotated[numpy.typing.ArrayLike, numpy.float32], acc: typing.Annotated[numpy.typing.ArrayLike, numpy.float32], mag: typing.Any, gps_t: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], gps_vel_n: typing.Annotated[numpy.typing.ArrayLike, numpy.float32]) -> tuple:
        """
        Batch run (GIL released). Returns (quat, bias, gps_acc_n, residual, flags).
        """
    def set_mag_dip(self, dip: typing.SupportsFloat | typing.SupportsIndex) -> None:
        ...
    def set_state(self, state: dict) -> str:
        """
        Restore a state from get_state(); unknown and missing keys are refused.
        """
    def update_acc(self, acc: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"]) -> MargUpdateResult_f32:
        ...
    def update_acc_mag(self, acc: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], mag: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"]) -> MargUpdateResult_f32:
        ...
    def update_gps_velocity(self, v_n: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], t: typing.SupportsFloat | typing.SupportsIndex) -> str:
        ...
    @property
    def at_rest(self) -> bool:
        ...
    @property
    def bias(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float32], "[3, 1]"]:
        """
        gyro bias [rad/s]
        """
    @property
    def gps_acc_available(self) -> bool:
        ...
    @property
    def gps_acc_n(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float32], "[3, 1]"]:
        ...
    @property
    def initialized(self) -> bool:
        ...
    @property
    def params(self) -> MargFilterParams_f32:
        ...
    @property
    def quat(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float32], "[4, 1]"]:
        """
        q_nb [w, x, y, z]
        """
class UpdateResult1_f64:
    """
    Outcome of one measurement update.
    """
    def __repr__(self) -> str:
        ...
    @property
    def accepted(self) -> bool:
        ...
    @property
    def innovation(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[1, 1]"]:
        ...
    @property
    def innovation_cov(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[1, 1]"]:
        ...
    @property
    def nis(self) -> float:
        ...
    @property
    def status(self) -> str:
        ...
class UpdateResult4_f64:
    """
    Outcome of one measurement update.
    """
    def __repr__(self) -> str:
        ...
    @property
    def accepted(self) -> bool:
        ...
    @property
    def innovation(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[4, 1]"]:
        ...
    @property
    def innovation_cov(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[4, 4]"]:
        ...
    @property
    def nis(self) -> float:
        ...
    @property
    def status(self) -> str:
        ...
class NavFilter13Params_f64:
    """
    Parameters of NavFilter13 (nav_filter13.hpp).
    """
    @staticmethod
    def fields() -> list:
        """
        The declaration table: a list of (name, default, unit, doc).
        """
    @staticmethod
    def from_dict(d: dict) -> NavFilter13Params_f64:
        """
        From a dict of some fields (the others keep their defaults); unknown keys refused.
        """
    def __init__(self) -> None:
        ...
    def __repr__(self) -> str:
        ...
    def to_dict(self) -> dict:
        ...
    @property
    def acc_bias_noise(self) -> float:
        """
        accelerometer-bias random-walk density [m/s^3/sqrt(Hz)]
        """
    @acc_bias_noise.setter
    def acc_bias_noise(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_noise(self) -> float:
        """
        accelerometer white-noise density (velocity random walk) [m/s^2/sqrt(Hz)]
        """
    @acc_noise.setter
    def acc_noise(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_range(self) -> float:
        """
        accelerometer range per axis, as gyro_range (0: unlimited) [m/s^2]
        """
    @acc_range.setter
    def acc_range(self, arg1: typing.Any) -> None:
        ...
    @property
    def cov_floor(self) -> float:
        """
        eigenvalue floor of the error covariance (0: off) [state units^2]
        """
    @cov_floor.setter
    def cov_floor(self, arg1: typing.Any) -> None:
        ...
    @property
    def earth_rotation(self) -> bool:
        """
        include the Earth rate, transport rate and Coriolis terms [-]
        """
    @earth_rotation.setter
    def earth_rotation(self, arg1: typing.Any) -> None:
        ...
    @property
    def gps_vel_sigma(self) -> float:
        """
        one-sigma of each measured velocity component [m/s]
        """
    @gps_vel_sigma.setter
    def gps_vel_sigma(self, arg1: typing.Any) -> None:
        ...
    @property
    def gyro_bias_noise(self) -> float:
        """
        gyro-bias random-walk density [rad/s^2/sqrt(Hz)]
        """
    @gyro_bias_noise.setter
    def gyro_bias_noise(self, arg1: typing.Any) -> None:
        ...
    @property
    def gyro_noise(self) -> float:
        """
        gyro white-noise density (angle random walk) [rad/s/sqrt(Hz)]
        """
    @gyro_noise.setter
    def gyro_noise(self, arg1: typing.Any) -> None:
        ...
    @property
    def gyro_range(self) -> float:
        """
        gyro range per axis: a reading at or above it is saturated and its step skipped (0: unlimited) [rad/s]
        """
    @gyro_range.setter
    def gyro_range(self, arg1: typing.Any) -> None:
        ...
    @property
    def max_dt(self) -> float:
        """
        longest accepted IMU step [s]
        """
    @max_dt.setter
    def max_dt(self, arg1: typing.Any) -> None:
        ...
    @property
    def ukf_alpha(self) -> float:
        """
        unscented transform: alpha [1]
        """
    @ukf_alpha.setter
    def ukf_alpha(self, arg1: typing.Any) -> None:
        ...
    @property
    def ukf_beta(self) -> float:
        """
        unscented transform: beta [1]
        """
    @ukf_beta.setter
    def ukf_beta(self, arg1: typing.Any) -> None:
        ...
    @property
    def ukf_kappa(self) -> float:
        """
        unscented transform: kappa (alpha^2 (12 + kappa) must be positive) [1]
        """
    @ukf_kappa.setter
    def ukf_kappa(self, arg1: typing.Any) -> None:
        ...
    @property
    def yaw_sigma(self) -> float:
        """
        one-sigma of the measured yaw [rad]
        """
    @yaw_sigma.setter
    def yaw_sigma(self, arg1: typing.Any) -> None:
        ...
class NavFilter13Ekf_f64:
    @staticmethod
    def state_fields() -> list:
        """
        The state's declaration table: (name, default, unit, doc).
        """
    def __init__(self, params: NavFilter13Params_f64) -> None:
        ...
    def get_state(self) -> dict:
        """
        The complete state as a dict of arrays and numbers (set_state restores it exactly).
        """
    def predict(self, omega_ib_b: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], f_ib_b: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], dt: typing.SupportsFloat | typing.SupportsIndex) -> str:
        ...
    def reset(self, v_n: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], q_nb: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[4, 1]"], acc_bias: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], gyro_bias: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], P: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[13, 13]"], lat: typing.SupportsFloat | typing.SupportsIndex, lon: typing.SupportsFloat | typing.SupportsIndex, h: typing.SupportsFloat | typing.SupportsIndex) -> str:
        ...
    def run(self, omega_ib_b: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], f_ib_b: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], t: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], dt: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], vel_t: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], vel: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], yaw_t: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], yaw: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], gate_vel: typing.SupportsFloat | typing.SupportsIndex = 0.0, gate_yaw: typing.SupportsFloat | typing.SupportsIndex = 0.0, return_covariance: bool = False, smooth: bool = False, segment: typing.SupportsInt | typing.SupportsIndex = 256, apply_at_start: bool = True) -> dict:
        """
        Batch run (GIL released). Returns a dict of arrays; with smooth, also 'smoothed': the Rauch-Tung-Striebel estimates (x, sigma, att_sigma, P) and the smoother's 'info'. apply_at_start: apply measurements at the state's time before the first step (a run from a reset state; false for a run that continues a previous one).
        """
    def set_position(self, lat: typing.SupportsFloat | typing.SupportsIndex, lon: typing.SupportsFloat | typing.SupportsIndex, h: typing.SupportsFloat | typing.SupportsIndex) -> str:
        ...
    def set_state(self, state: dict) -> str:
        """
        Restore a state from get_state(); unknown and missing keys are refused.
        """
    def update_velocity(self, v_n: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], gate: typing.SupportsFloat | typing.SupportsIndex = 0.0) -> UpdateResult3_f64:
        ...
    def update_velocity_yaw(self, v_n: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], yaw: typing.SupportsFloat | typing.SupportsIndex, gate: typing.SupportsFloat | typing.SupportsIndex = 0.0) -> UpdateResult4_f64:
        ...
    def update_yaw(self, yaw: typing.SupportsFloat | typing.SupportsIndex, gate: typing.SupportsFloat | typing.SupportsIndex = 0.0) -> UpdateResult1_f64:
        ...
    @property
    def covariance(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[13, 13]"]:
        ...
    @property
    def error_covariance(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[12, 12]"]:
        ...
    @property
    def initialized(self) -> bool:
        ...
    @property
    def params(self) -> NavFilter13Params_f64:
        ...
    @property
    def params_valid(self) -> bool:
        ...
    @property
    def time_update(self) -> str:
        ...
    @property
    def x(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[13, 1]"]:
        ...
class NavFilter13SecondOrder_f64:
    @staticmethod
    def state_fields() -> list:
        """
        The state's declaration table: (name, default, unit, doc).
        """
    def __init__(self, params: NavFilter13Params_f64) -> None:
        ...
    def get_state(self) -> dict:
        """
        The complete state as a dict of arrays and numbers (set_state restores it exactly).
        """
    def predict(self, omega_ib_b: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], f_ib_b: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], dt: typing.SupportsFloat | typing.SupportsIndex) -> str:
        ...
    def reset(self, v_n: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], q_nb: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[4, 1]"], acc_bias: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], gyro_bias: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], P: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[13, 13]"], lat: typing.SupportsFloat | typing.SupportsIndex, lon: typing.SupportsFloat | typing.SupportsIndex, h: typing.SupportsFloat | typing.SupportsIndex) -> str:
        ...
    def run(self, omega_ib_b: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], f_ib_b: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], t: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], dt: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], vel_t: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], vel: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], yaw_t: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], yaw: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], gate_vel: typing.SupportsFloat | typing.SupportsIndex = 0.0, gate_yaw: typing.SupportsFloat | typing.SupportsIndex = 0.0, return_covariance: bool = False, smooth: bool = False, segment: typing.SupportsInt | typing.SupportsIndex = 256, apply_at_start: bool = True) -> dict:
        """
        Batch run (GIL released). Returns a dict of arrays; with smooth, also 'smoothed': the Rauch-Tung-Striebel estimates (x, sigma, att_sigma, P) and the smoother's 'info'. apply_at_start: apply measurements at the state's time before the first step (a run from a reset state; false for a run that continues a previous one).
        """
    def set_position(self, lat: typing.SupportsFloat | typing.SupportsIndex, lon: typing.SupportsFloat | typing.SupportsIndex, h: typing.SupportsFloat | typing.SupportsIndex) -> str:
        ...
    def set_state(self, state: dict) -> str:
        """
        Restore a state from get_state(); unknown and missing keys are refused.
        """
    def update_velocity(self, v_n: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], gate: typing.SupportsFloat | typing.SupportsIndex = 0.0) -> UpdateResult3_f64:
        ...
    def update_velocity_yaw(self, v_n: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], yaw: typing.SupportsFloat | typing.SupportsIndex, gate: typing.SupportsFloat | typing.SupportsIndex = 0.0) -> UpdateResult4_f64:
        ...
    def update_yaw(self, yaw: typing.SupportsFloat | typing.SupportsIndex, gate: typing.SupportsFloat | typing.SupportsIndex = 0.0) -> UpdateResult1_f64:
        ...
    @property
    def covariance(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[13, 13]"]:
        ...
    @property
    def error_covariance(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[12, 12]"]:
        ...
    @property
    def initialized(self) -> bool:
        ...
    @property
    def params(self) -> NavFilter13Params_f64:
        ...
    @property
    def params_valid(self) -> bool:
        ...
    @property
    def time_update(self) -> str:
        ...
    @property
    def x(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[13, 1]"]:
        ...
class NavFilter13Ukf_f64:
    @staticmethod
    def state_fields() -> list:
        """
        The state's declaration table: (name, default, unit, doc).
        """
    def __init__(self, params: NavFilter13Params_f64) -> None:
        ...
    def get_state(self) -> dict:
        """
        The complete state as a dict of arrays and numbers (set_state restores it exactly).
        """
    def predict(self, omega_ib_b: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], f_ib_b: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], dt: typing.SupportsFloat | typing.SupportsIndex) -> str:
        ...
    def reset(self, v_n: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], q_nb: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[4, 1]"], acc_bias: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], gyro_bias: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], P: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[13, 13]"], lat: typing.SupportsFloat | typing.SupportsIndex, lon: typing.SupportsFloat | typing.SupportsIndex, h: typing.SupportsFloat | typing.SupportsIndex) -> str:
        ...
    def run(self, omega_ib_b: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], f_ib_b: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], t: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], dt: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], vel_t: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], vel: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], yaw_t: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], yaw: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], gate_vel: typing.SupportsFloat | typing.SupportsIndex = 0.0, gate_yaw: typing.SupportsFloat | typing.SupportsIndex = 0.0, return_covariance: bool = False, smooth: bool = False, segment: typing.SupportsInt | typing.SupportsIndex = 256, apply_at_start: bool = True) -> dict:
        """
        Batch run (GIL released). Returns a dict of arrays; with smooth, also 'smoothed': the Rauch-Tung-Striebel estimates (x, sigma, att_sigma, P) and the smoother's 'info'. apply_at_start: apply measurements at the state's time before the first step (a run from a reset state; false for a run that continues a previous one).
        """
    def set_position(self, lat: typing.SupportsFloat | typing.SupportsIndex, lon: typing.SupportsFloat | typing.SupportsIndex, h: typing.SupportsFloat | typing.SupportsIndex) -> str:
        ...
    def set_state(self, state: dict) -> str:
        """
        Restore a state from get_state(); unknown and missing keys are refused.
        """
    def update_velocity(self, v_n: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], gate: typing.SupportsFloat | typing.SupportsIndex = 0.0) -> UpdateResult3_f64:
        ...
    def update_velocity_yaw(self, v_n: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], yaw: typing.SupportsFloat | typing.SupportsIndex, gate: typing.SupportsFloat | typing.SupportsIndex = 0.0) -> UpdateResult4_f64:
        ...
    def update_yaw(self, yaw: typing.SupportsFloat | typing.SupportsIndex, gate: typing.SupportsFloat | typing.SupportsIndex = 0.0) -> UpdateResult1_f64:
        ...
    @property
    def covariance(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[13, 13]"]:
        ...
    @property
    def error_covariance(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[12, 12]"]:
        ...
    @property
    def initialized(self) -> bool:
        ...
    @property
    def params(self) -> NavFilter13Params_f64:
        ...
    @property
    def params_valid(self) -> bool:
        ...
    @property
    def time_update(self) -> str:
        ...
    @property
    def x(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[13, 1]"]:
        ...
class UpdateResult1_f32:
    """
    Outcome of one measurement update.
    """
    def __repr__(self) -> str:
        ...
    @property
    def accepted(self) -> bool:
        ...
    @property
    def innovation(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float32], "[1, 1]"]:
        ...
    @property
    def innovation_cov(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float32], "[1, 1]"]:
        ...
    @property
    def nis(self) -> float:
        ...
    @property
    def status(self) -> str:
        ...
class UpdateResult4_f32:
    """
    Outcome of one measurement update.
    """
    def __repr__(self) -> str:
        ...
    @property
    def accepted(self) -> bool:
        ...
    @property
    def innovation(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float32], "[4, 1]"]:
        ...
    @property
    def innovation_cov(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float32], "[4, 4]"]:
        ...
    @property
    def nis(self) -> float:
        ...
    @property
    def status(self) -> str:
        ...
class NavFilter13Params_f32:
    """
    Parameters of NavFilter13 (nav_filter13.hpp).
    """
    @staticmethod
    def fields() -> list:
        """
        The declaration table: a list of (name, default, unit, doc).
        """
    @staticmethod
    def from_dict(d: dict) -> NavFilter13Params_f32:
        """
        From a dict of some fields (the others keep their defaults); unknown keys refused.
        """
    def __init__(self) -> None:
        ...
    def __repr__(self) -> str:
        ...
    def to_dict(self) -> dict:
        ...
    @property
    def acc_bias_noise(self) -> float:
        """
        accelerometer-bias random-walk density [m/s^3/sqrt(Hz)]
        """
    @acc_bias_noise.setter
    def acc_bias_noise(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_noise(self) -> float:
        """
        accelerometer white-noise density (velocity random walk) [m/s^2/sqrt(Hz)]
        """
    @acc_noise.setter
    def acc_noise(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_range(self) -> float:
        """
        accelerometer range per axis, as gyro_range (0: unlimited) [m/s^2]
        """
    @acc_range.setter
    def acc_range(self, arg1: typing.Any) -> None:
        ...
    @property
    def cov_floor(self) -> float:
        """
        eigenvalue floor of the error covariance (0: off) [state units^2]
        """
    @cov_floor.setter
    def cov_floor(self, arg1: typing.Any) -> None:
        ...
    @property
    def earth_rotation(self) -> bool:
        """
        include the Earth rate, transport rate and Coriolis terms [-]
        """
    @earth_rotation.setter
    def earth_rotation(self, arg1: typing.Any) -> None:
        ...
    @property
    def gps_vel_sigma(self) -> float:
        """
        one-sigma of each measured velocity component [m/s]
        """
    @gps_vel_sigma.setter
    def gps_vel_sigma(self, arg1: typing.Any) -> None:
        ...
    @property
    def gyro_bias_noise(self) -> float:
        """
        gyro-bias random-walk density [rad/s^2/sqrt(Hz)]
        """
    @gyro_bias_noise.setter
    def gyro_bias_noise(self, arg1: typing.Any) -> None:
        ...
    @property
    def gyro_noise(self) -> float:
        """
        gyro white-noise density (angle random walk) [rad/s/sqrt(Hz)]
        """
    @gyro_noise.setter
    def gyro_noise(self, arg1: typing.Any) -> None:
        ...
    @property
    def gyro_range(self) -> float:
        """
        gyro range per axis: a reading at or above it is saturated and its step skipped (0: unlimited) [rad/s]
        """
    @gyro_range.setter
    def gyro_range(self, arg1: typing.Any) -> None:
        ...
    @property
    def max_dt(self) -> float:
        """
        longest accepted IMU step [s]
        """
    @max_dt.setter
    def max_dt(self, arg1: typing.Any) -> None:
        ...
    @property
    def ukf_alpha(self) -> float:
        """
        unscented transform: alpha [1]
        """
    @ukf_alpha.setter
    def ukf_alpha(self, arg1: typing.Any) -> None:
        ...
    @property
    def ukf_beta(self) -> float:
        """
        unscented transform: beta [1]
        """
    @ukf_beta.setter
    def ukf_beta(self, arg1: typing.Any) -> None:
        ...
    @property
    def ukf_kappa(self) -> float:
        """
        unscented transform: kappa (alpha^2 (12 + kappa) must be positive) [1]
        """
    @ukf_kappa.setter
    def ukf_kappa(self, arg1: typing.Any) -> None:
        ...
    @property
    def yaw_sigma(self) -> float:
        """
        one-sigma of the measured yaw [rad]
        """
    @yaw_sigma.setter
    def yaw_sigma(self, arg1: typing.Any) -> None:
        ...
class NavFilter13Ekf_f32:
    @staticmethod
    def state_fields() -> list:
        """
        The state's declaration table: (name, default, unit, doc).
        """
    def __init__(self, params: NavFilter13Params_f32) -> None:
        ...
    def get_state(self) -> dict:
        """
        The complete state as a dict of arrays and numbers (set_state restores it exactly).
        """
    def predict(self, omega_ib_b: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], f_ib_b: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], dt: typing.SupportsFloat | typing.SupportsIndex) -> str:
        ...
    def reset(self, v_n: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], q_nb: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[4, 1]"], acc_bias: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], gyro_bias: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], P: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[13, 13]"], lat: typing.SupportsFloat | typing.SupportsIndex, lon: typing.SupportsFloat | typing.SupportsIndex, h: typing.SupportsFloat | typing.SupportsIndex) -> str:
        ...
    def run(self, omega_ib_b: typing.Annotated[numpy.typing.ArrayLike, numpy.float32], f_ib_b: typing.Annotated[numpy.typing.ArrayLike, numpy.float32], t: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], dt: typing.Annotated[numpy.typing.ArrayLike, numpy.float32], vel_t: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], vel: typing.Annotated[numpy.typing.ArrayLike, numpy.float32], yaw_t: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], yaw: typing.Annotated[numpy.typing.ArrayLike, numpy.float32], gate_vel: typing.SupportsFloat | typing.SupportsIndex = 0.0, gate_yaw: typing.SupportsFloat | typing.SupportsIndex = 0.0, return_covariance: bool = False, smooth: bool = False, segment: typing.SupportsInt | typing.SupportsIndex = 256, apply_at_start: bool = True) -> dict:
        """
        Batch run (GIL released). Returns a dict of arrays; with smooth, also 'smoothed': the Rauch-Tung-Striebel estimates (x, sigma, att_sigma, P) and the smoother's 'info'. apply_at_start: apply measurements at the state's time before the first step (a run from a reset state; false for a run that continues a previous one).
        """
    def set_position(self, lat: typing.SupportsFloat | typing.SupportsIndex, lon: typing.SupportsFloat | typing.SupportsIndex, h: typing.SupportsFloat | typing.SupportsIndex) -> str:
        ...
    def set_state(self, state: dict) -> str:
        """
        Restore a state from get_state(); unknown and missing keys are refused.
        """
    def update_velocity(self, v_n: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], gate: typing.SupportsFloat | typing.SupportsIndex = 0.0) -> UpdateResult3_f32:
        ...
    def update_velocity_yaw(self, v_n: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], yaw: typing.SupportsFloat | typing.SupportsIndex, gate: typing.SupportsFloat | typing.SupportsIndex = 0.0) -> UpdateResult4_f32:
        ...
    def update_yaw(self, yaw: typing.SupportsFloat | typing.SupportsIndex, gate: typing.SupportsFloat | typing.SupportsIndex = 0.0) -> UpdateResult1_f32:
        ...
    @property
    def covariance(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float32], "[13, 13]"]:
        ...
    @property
    def error_covariance(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float32], "[12, 12]"]:
        ...
    @property
    def initialized(self) -> bool:
        ...
    @property
    def params(self) -> NavFilter13Params_f32:
        ...
    @property
    def params_valid(self) -> bool:
        ...
    @property
    def time_update(self) -> str:
        ...
    @property
    def x(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float32], "[13, 1]"]:
        ...
class NavFilter13SecondOrder_f32:
    @staticmethod
    def state_fields() -> list:
        """
        The state's declaration table: (name, default, unit, doc).
        """
    def __init__(self, params: NavFilter13Params_f32) -> None:
        ...
    def get_state(self) -> dict:
        """
        The complete state as a dict of arrays and numbers (set_state restores it exactly).
        """
    def predict(self, omega_ib_b: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], f_ib_b: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], dt: typing.SupportsFloat | typing.SupportsIndex) -> str:
        ...
    def reset(self, v_n: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], q_nb: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[4, 1]"], acc_bias: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], gyro_bias: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], P: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[13, 13]"], lat: typing.SupportsFloat | typing.SupportsIndex, lon: typing.SupportsFloat | typing.SupportsIndex, h: typing.SupportsFloat | typing.SupportsIndex) -> str:
        ...
    def run(self, omega_ib_b: typing.Annotated[numpy.typing.ArrayLike, numpy.float32], f_ib_b: typing.Annotated[numpy.typing.ArrayLike, numpy.float32], t: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], dt: typing.Annotated[numpy.typing.ArrayLike, numpy.float32], vel_t: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], vel: typing.Annotated[numpy.typing.ArrayLike, numpy.float32], yaw_t: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], yaw: typing.Annotated[numpy.typing.ArrayLike, numpy.float32], gate_vel: typing.SupportsFloat | typing.SupportsIndex = 0.0, gate_yaw: typing.SupportsFloat | typing.SupportsIndex = 0.0, return_covariance: bool = False, smooth: bool = False, segment: typing.SupportsInt | typing.SupportsIndex = 256, apply_at_start: bool = True) -> dict:
        """
        Batch run (GIL released). Returns a dict of arrays; with smooth, also 'smoothed': the Rauch-Tung-Striebel estimates (x, sigma, att_sigma, P) and the smoother's 'info'. apply_at_start: apply measurements at the state's time before the first step (a run from a reset state; false for a run that continues a previous one).
        """
    def set_position(self, lat: typing.SupportsFloat | typing.SupportsIndex, lon: typing.SupportsFloat | typing.SupportsIndex, h: typing.SupportsFloat | typing.SupportsIndex) -> str:
        ...
    def set_state(self, state: dict) -> str:
        """
        Restore a state from get_state(); unknown and missing keys are refused.
        """
    def update_velocity(self, v_n: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], gate: typing.SupportsFloat | typing.SupportsIndex = 0.0) -> UpdateResult3_f32:
        ...
    def update_velocity_yaw(self, v_n: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], yaw: typing.SupportsFloat | typing.SupportsIndex, gate: typing.SupportsFloat | typing.SupportsIndex = 0.0) -> UpdateResult4_f32:
        ...
    def update_yaw(self, yaw: typing.SupportsFloat | typing.SupportsIndex, gate: typing.SupportsFloat | typing.SupportsIndex = 0.0) -> UpdateResult1_f32:
        ...
    @property
    def covariance(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float32], "[13, 13]"]:
        ...
    @property
    def error_covariance(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float32], "[12, 12]"]:
        ...
    @property
    def initialized(self) -> bool:
        ...
    @property
    def params(self) -> NavFilter13Params_f32:
        ...
    @property
    def params_valid(self) -> bool:
        ...
    @property
    def time_update(self) -> str:
        ...
    @property
    def x(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float32], "[13, 1]"]:
        ...
class NavFilter13Ukf_f32:
    @staticmethod
    def state_fields() -> list:
        """
        The state's declaration table: (name, default, unit, doc).
        """
    def __init__(self, params: NavFilter13Params_f32) -> None:
        ...
    def get_state(self) -> dict:
        """
        The complete state as a dict of arrays and numbers (set_state restores it exactly).
        """
    def predict(self, omega_ib_b: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], f_ib_b: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], dt: typing.SupportsFloat | typing.SupportsIndex) -> str:
        ...
    def reset(self, v_n: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], q_nb: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[4, 1]"], acc_bias: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], gyro_bias: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], P: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[13, 13]"], lat: typing.SupportsFloat | typing.SupportsIndex, lon: typing.SupportsFloat | typing.SupportsIndex, h: typing.SupportsFloat | typing.SupportsIndex) -> str:
        ...
    def run(self, omega_ib_b: typing.Annotated[numpy.typing.ArrayLike, numpy.float32], f_ib_b: typing.Annotated[numpy.typing.ArrayLike, numpy.float32], t: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], dt: typing.Annotated[numpy.typing.ArrayLike, numpy.float32], vel_t: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], vel: typing.Annotated[numpy.typing.ArrayLike, numpy.float32], yaw_t: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], yaw: typing.Annotated[numpy.typing.ArrayLike, numpy.float32], gate_vel: typing.SupportsFloat | typing.SupportsIndex = 0.0, gate_yaw: typing.SupportsFloat | typing.SupportsIndex = 0.0, return_covariance: bool = False, smooth: bool = False, segment: typing.SupportsInt | typing.SupportsIndex = 256, apply_at_start: bool = True) -> dict:
        """
        Batch run (GIL released). Returns a dict of arrays; with smooth, also 'smoothed': the Rauch-Tung-Striebel estimates (x, sigma, att_sigma, P) and the smoother's 'info'. apply_at_start: apply measurements at the state's time before the first step (a run from a reset state; false for a run that continues a previous one).
        """
    def set_position(self, lat: typing.SupportsFloat | typing.SupportsIndex, lon: typing.SupportsFloat | typing.SupportsIndex, h: typing.SupportsFloat | typing.SupportsIndex) -> str:
        ...
    def set_state(self, state: dict) -> str:
        """
        Restore a state from get_state(); unknown and missing keys are refused.
        """
    def update_velocity(self, v_n: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], gate: typing.SupportsFloat | typing.SupportsIndex = 0.0) -> UpdateResult3_f32:
        ...
    def update_velocity_yaw(self, v_n: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], yaw: typing.SupportsFloat | typing.SupportsIndex, gate: typing.SupportsFloat | typing.SupportsIndex = 0.0) -> UpdateResult4_f32:
        ...
    def update_yaw(self, yaw: typing.SupportsFloat | typing.SupportsIndex, gate: typing.SupportsFloat | typing.SupportsIndex = 0.0) -> UpdateResult1_f32:
        ...
    @property
    def covariance(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float32], "[13, 13]"]:
        ...
    @property
    def error_covariance(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float32], "[12, 12]"]:
        ...
    @property
    def initialized(self) -> bool:
        ...
    @property
    def params(self) -> NavFilter13Params_f32:
        ...
    @property
    def params_valid(self) -> bool:
        ...
    @property
    def time_update(self) -> str:
        ...
    @property
    def x(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float32], "[13, 1]"]:
        ...
class GpsInsUpdate1_f64:
    """
    Outcome of one GpsInsFilter update: status, innovation (INS minus aid), its covariance, NIS, decision (code, see decision_names()), inflation.
    """
    def __repr__(self) -> str:
        ...
    @property
    def accepted(self) -> bool:
        ...
    @property
    def decision(self) -> int:
        ...
    @property
    def inflation(self) -> float:
        ...
    @property
    def innovation(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[1, 1]"]:
        ...
    @property
    def innovation_cov(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[1, 1]"]:
        ...
    @property
    def nis(self) -> float:
        ...
    @property
    def status(self) -> str:
        ...
class GpsInsUpdate2_f64:
    """
    Outcome of one GpsInsFilter update: status, innovation (INS minus aid), its covariance, NIS, decision (code, see decision_names()), inflation.
    """
    def __repr__(self) -> str:
        ...
    @property
    def accepted(self) -> bool:
        ...
    @property
    def decision(self) -> int:
        ...
    @property
    def inflation(self) -> float:
        ...
    @property
    def innovation(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[2, 1]"]:
        ...
    @property
    def innovation_cov(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[2, 2]"]:
        ...
    @property
    def nis(self) -> float:
        ...
    @property
    def status(self) -> str:
        ...
class GpsInsUpdate3_f64:
    """
    Outcome of one GpsInsFilter update: status, innovation (INS minus aid), its covariance, NIS, decision (code, see decision_names()), inflation.
    """
    def __repr__(self) -> str:
        ...
    @property
    def accepted(self) -> bool:
        ...
    @property
    def decision(self) -> int:
        ...
    @property
    def inflation(self) -> float:
        ...
    @property
    def innovation(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[3, 1]"]:
        ...
    @property
    def innovation_cov(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[3, 3]"]:
        ...
    @property
    def nis(self) -> float:
        ...
    @property
    def status(self) -> str:
        ...
class GpsInsParams_f64:
    """
    Parameters of GpsInsFilter (nav/gps_ins/params.hpp).
    """
    @staticmethod
    def fields() -> list:
        """
        The declaration table: a list of (name, default, unit, doc).
        """
    @staticmethod
    def from_dict(d: dict) -> GpsInsParams_f64:
        """
        From a dict of some fields (the others keep their defaults); unknown keys refused.
        """
    def __init__(self) -> None:
        ...
    def __repr__(self) -> str:
        ...
    def to_dict(self) -> dict:
        ...
    @property
    def acc_bias_noise(self) -> float:
        """
        accelerometer-bias random-walk density [m/s^3/sqrt(Hz)]
        """
    @acc_bias_noise.setter
    def acc_bias_noise(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_bias_tau(self) -> float:
        """
        Gauss-Markov time constant of the accelerometer bias (0: random walk) [s]
        """
    @acc_bias_tau.setter
    def acc_bias_tau(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_noise(self) -> float:
        """
        accelerometer white-noise density (velocity random walk) [m/s^2/sqrt(Hz)]
        """
    @acc_noise.setter
    def acc_noise(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_range(self) -> float:
        """
        accelerometer range per axis, as gyro_range (0: unlimited) [m/s^2]
        """
    @acc_range.setter
    def acc_range(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_scale_noise(self) -> float:
        """
        accelerometer scale-factor random-walk density (scale-factor states only) [1/sqrt(s)]
        """
    @acc_scale_noise.setter
    def acc_scale_noise(self, arg1: typing.Any) -> None:
        ...
    @property
    def adapt_gain(self) -> float:
        """
        step of the adaptation per GNSS update (natural log of the scale) [1]
        """
    @adapt_gain.setter
    def adapt_gain(self, arg1: typing.Any) -> None:
        ...
    @property
    def adapt_q_max(self) -> float:
        """
        largest process-noise scale of the innovation-based adaptation (1: off) [1]
        """
    @adapt_q_max.setter
    def adapt_q_max(self, arg1: typing.Any) -> None:
        ...
    @property
    def align_course_distance(self) -> float:
        """
        distance between the position fixes whose course gives the heading (position-only GNSS) [m]
        """
    @align_course_distance.setter
    def align_course_distance(self, arg1: typing.Any) -> None:
        ...
    @property
    def align_level_sigma(self) -> float:
        """
        roll/pitch one-sigma after an alignment in motion without GNSS velocity [rad]
        """
    @align_level_sigma.setter
    def align_level_sigma(self, arg1: typing.Any) -> None:
        ...
    @property
    def align_motion_max(self) -> float:
        """
        longest window of an alignment in motion (then it restarts) [s]
        """
    @align_motion_max.setter
    def align_motion_max(self, arg1: typing.Any) -> None:
        ...
    @property
    def align_motion_time(self) -> float:
        """
        shortest window of an alignment in motion [s]
        """
    @align_motion_time.setter
    def align_motion_time(self, arg1: typing.Any) -> None:
        ...
    @property
    def align_time(self) -> float:
        """
        duration of the static alignment (still samples; motion restarts it) [s]
        """
    @align_time.setter
    def align_time(self, arg1: typing.Any) -> None:
        ...
    @property
    def baro_offset_noise(self) -> float:
        """
        random-walk density of the altimeter offset [m/sqrt(s)]
        """
    @baro_offset_noise.setter
    def baro_offset_noise(self, arg1: typing.Any) -> None:
        ...
    @property
    def baro_rate_baseline(self) -> float:
        """
        baseline of the altimeter's vertical-velocity difference [s]
        """
    @baro_rate_baseline.setter
    def baro_rate_baseline(self, arg1: typing.Any) -> None:
        ...
    @property
    def baro_sigma(self) -> float:
        """
        one-sigma of an altimeter height [m]
        """
    @baro_sigma.setter
    def baro_sigma(self, arg1: typing.Any) -> None:
        ...
    @property
    def baro_vd_sigma(self) -> float:
        """
        one-sigma of the altimeter's vertical velocity [m/s]
        """
    @baro_vd_sigma.setter
    def baro_vd_sigma(self, arg1: typing.Any) -> None:
        ...
    @property
    def compass_sigma(self) -> float:
        """
        one-sigma of a compass heading [rad]
        """
    @compass_sigma.setter
    def compass_sigma(self, arg1: typing.Any) -> None:
        ...
    @property
    def cov_floor(self) -> float:
        """
        eigenvalue floor of the error covariance (0: off) [state units^2]
        """
    @cov_floor.setter
    def cov_floor(self, arg1: typing.Any) -> None:
        ...
    @property
    def declination(self) -> float:
        """
        magnetic declination, east of true north (added to compass headings) [rad]
        """
    @declination.setter
    def declination(self, arg1: typing.Any) -> None:
        ...
    @property
    def earth_rotation(self) -> bool:
        """
        include the Earth rate, transport rate and Coriolis terms [-]
        """
    @earth_rotation.setter
    def earth_rotation(self, arg1: typing.Any) -> None:
        ...
    @property
    def gate_baro(self) -> float:
        """
        NIS gate of the altimeter (0: off) [1 (chi-square, 1 dof)]
        """
    @gate_baro.setter
    def gate_baro(self, arg1: typing.Any) -> None:
        ...
    @property
    def gate_compass(self) -> float:
        """
        NIS gate of the compass (0: off) [1 (chi-square, 1 dof)]
        """
    @gate_compass.setter
    def gate_compass(self, arg1: typing.Any) -> None:
        ...
    @property
    def gate_gps_pos(self) -> float:
        """
        NIS gate of the GPS position (0: off) [1 (chi-square, 3 dof)]
        """
    @gate_gps_pos.setter
    def gate_gps_pos(self, arg1: typing.Any) -> None:
        ...
    @property
    def gate_gps_vel(self) -> float:
        """
        NIS gate of the GPS velocity (0: off) [1 (chi-square, 3 dof)]
        """
    @gate_gps_vel.setter
    def gate_gps_vel(self, arg1: typing.Any) -> None:
        ...
    @property
    def gate_mag(self) -> float:
        """
        NIS gate of the magnetometer heading (0: off) [1 (chi-square, 1 dof)]
        """
    @gate_mag.setter
    def gate_mag(self, arg1: typing.Any) -> None:
        ...
    @property
    def gate_nhc(self) -> float:
        """
        NIS gate of the non-holonomic constraint (0: off) [1 (chi-square, 2 dof)]
        """
    @gate_nhc.setter
    def gate_nhc(self, arg1: typing.Any) -> None:
        ...
    @property
    def gate_odometer(self) -> float:
        """
        NIS gate of the odometer (0: off) [1 (chi-square, 1 dof)]
        """
    @gate_odometer.setter
    def gate_odometer(self, arg1: typing.Any) -> None:
        ...
    @property
    def gate_zupt(self) -> float:
        """
        NIS gate of the zero-velocity and zero-rate updates (0: off) [1 (chi-square, 3 dof)]
        """
    @gate_zupt.setter
    def gate_zupt(self, arg1: typing.Any) -> None:
        ...
    @property
    def gps_dgnss_sigma_min(self) -> float:
        """
        floor of a GPS position one-sigma of a DGNSS, SBAS or PPP solution [m]
        """
    @gps_dgnss_sigma_min.setter
    def gps_dgnss_sigma_min(self, arg1: typing.Any) -> None:
        ...
    @property
    def gps_error_tau(self) -> float:
        """
        correlation time of the position errors of RTK-float, DGNSS and single solutions (0: white) [s]
        """
    @gps_error_tau.setter
    def gps_error_tau(self, arg1: typing.Any) -> None:
        ...
    @property
    def gps_float_sigma_min(self) -> float:
        """
        floor of a GPS position one-sigma of an RTK-float solution [m]
        """
    @gps_float_sigma_min.setter
    def gps_float_sigma_min(self, arg1: typing.Any) -> None:
        ...
    @property
    def gps_pos_sigma_h(self) -> float:
        """
        horizontal one-sigma of a GPS position (per-fix sigma overrides) [m]
        """
    @gps_pos_sigma_h.setter
    def gps_pos_sigma_h(self, arg1: typing.Any) -> None:
        ...
    @property
    def gps_pos_sigma_min(self) -> float:
        """
        floor of a GPS position one-sigma (given or per fix) of an RTK-fixed solution or one of unknown kind [m]
        """
    @gps_pos_sigma_min.setter
    def gps_pos_sigma_min(self, arg1: typing.Any) -> None:
        ...
    @property
    def gps_pos_sigma_v(self) -> float:
        """
        vertical one-sigma of a GPS position [m]
        """
    @gps_pos_sigma_v.setter
    def gps_pos_sigma_v(self, arg1: typing.Any) -> None:
        ...
    @property
    def gps_robust_k(self) -> float:
        """
        Huber threshold of the GNSS aids: an innovation component beyond it (in its sigmas) is down-weighted (0: off) [1]
        """
    @gps_robust_k.setter
    def gps_robust_k(self, arg1: typing.Any) -> None:
        ...
    @property
    def gps_single_sigma_min(self) -> float:
        """
        floor of a GPS position one-sigma of a single (standalone) solution [m]
        """
    @gps_single_sigma_min.setter
    def gps_single_sigma_min(self, arg1: typing.Any) -> None:
        ...
    @property
    def gps_time_offset(self) -> float:
        """
        added to the GNSS times to put them on the IMU clock (a receiver latency L: -L) [s]
        """
    @gps_time_offset.setter
    def gps_time_offset(self, arg1: typing.Any) -> None:
        ...
    @property
    def gps_time_sigma(self) -> float:
        """
        one-sigma of the GNSS time on the IMU clock [s]
        """
    @gps_time_sigma.setter
    def gps_time_sigma(self, arg1: typing.Any) -> None:
        ...
    @property
    def gps_vel_sigma(self) -> float:
        """
        one-sigma of each GPS velocity component [m/s]
        """
    @gps_vel_sigma.setter
    def gps_vel_sigma(self, arg1: typing.Any) -> None:
        ...
    @property
    def gps_vel_sigma_min(self) -> float:
        """
        floor of a GPS velocity one-sigma (given or per fix) [m/s]
        """
    @gps_vel_sigma_min.setter
    def gps_vel_sigma_min(self, arg1: typing.Any) -> None:
        ...
    @property
    def gps_vertical_floor_ratio(self) -> float:
        """
        floor of a GPS position's down one-sigma over the north and east floor of its solution kind [1]
        """
    @gps_vertical_floor_ratio.setter
    def gps_vertical_floor_ratio(self, arg1: typing.Any) -> None:
        ...
    @property
    def gyro_bias_noise(self) -> float:
        """
        gyro-bias random-walk density [rad/s^2/sqrt(Hz)]
        """
    @gyro_bias_noise.setter
    def gyro_bias_noise(self, arg1: typing.Any) -> None:
        ...
    @property
    def gyro_bias_tau(self) -> float:
        """
        Gauss-Markov time constant of the gyro bias (0: random walk) [s]
        """
    @gyro_bias_tau.setter
    def gyro_bias_tau(self, arg1: typing.Any) -> None:
        ...
    @property
    def gyro_noise(self) -> float:
        """
        gyro white-noise density (angle random walk) [rad/s/sqrt(Hz)]
        """
    @gyro_noise.setter
    def gyro_noise(self, arg1: typing.Any) -> None:
        ...
    @property
    def gyro_range(self) -> float:
        """
        gyro range per axis: a reading at or above it is saturated and its step skipped (0: unlimited) [rad/s]
        """
    @gyro_range.setter
    def gyro_range(self, arg1: typing.Any) -> None:
        ...
    @property
    def gyro_rate_noise(self) -> float:
        """
        rate-proportional attitude process noise: density gyro_rate_noise * |w - b| (0: off); the attitude filters apply it to the tilt only [1/sqrt(Hz)]
        """
    @gyro_rate_noise.setter
    def gyro_rate_noise(self, arg1: typing.Any) -> None:
        ...
    @property
    def gyro_scale_noise(self) -> float:
        """
        gyro scale-factor random-walk density (scale-factor states only) [1/sqrt(s)]
        """
    @gyro_scale_noise.setter
    def gyro_scale_noise(self, arg1: typing.Any) -> None:
        ...
    @property
    def heading_from_gps(self) -> bool:
        """
        initialize the heading from the GPS track (without compass) [-]
        """
    @heading_from_gps.setter
    def heading_from_gps(self, arg1: typing.Any) -> None:
        ...
    @property
    def imu_rotation(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[3, 3]"]:
        """
        rotation from the IMU axes to the body axes: body = imu_rotation imu [1]
        """
    @imu_rotation.setter
    def imu_rotation(self, arg1: typing.Any) -> None:
        ...
    @property
    def inflate_after(self) -> float:
        """
        consecutive gate rejections of a GNSS aid after which the next failing fix inflates the covariance (0: never) [1]
        """
    @inflate_after.setter
    def inflate_after(self, arg1: typing.Any) -> None:
        ...
    @property
    def inflate_max(self) -> float:
        """
        largest covariance inflation; a fix that needs more resets the state to it [1]
        """
    @inflate_max.setter
    def inflate_max(self, arg1: typing.Any) -> None:
        ...
    @property
    def init_acc_bias_sigma(self) -> float:
        """
        accelerometer-bias one-sigma at the start of navigation [m/s^2]
        """
    @init_acc_bias_sigma.setter
    def init_acc_bias_sigma(self, arg1: typing.Any) -> None:
        ...
    @property
    def init_acc_scale_sigma(self) -> float:
        """
        accelerometer scale-factor one-sigma at the start of navigation (scale-factor states only) [1]
        """
    @init_acc_scale_sigma.setter
    def init_acc_scale_sigma(self, arg1: typing.Any) -> None:
        ...
    @property
    def init_gyro_bias_sigma(self) -> float:
        """
        gyro-bias one-sigma at the start of navigation [rad/s]
        """
    @init_gyro_bias_sigma.setter
    def init_gyro_bias_sigma(self, arg1: typing.Any) -> None:
        ...
    @property
    def init_gyro_scale_sigma(self) -> float:
        """
        gyro scale-factor one-sigma at the start of navigation (scale-factor states only) [1]
        """
    @init_gyro_scale_sigma.setter
    def init_gyro_scale_sigma(self, arg1: typing.Any) -> None:
        ...
    @property
    def init_level_sigma(self) -> float:
        """
        roll/pitch one-sigma after the alignment [rad]
        """
    @init_level_sigma.setter
    def init_level_sigma(self, arg1: typing.Any) -> None:
        ...
    @property
    def init_vel_sigma(self) -> float:
        """
        velocity one-sigma at the start of navigation [m/s]
        """
    @init_vel_sigma.setter
    def init_vel_sigma(self, arg1: typing.Any) -> None:
        ...
    @property
    def init_yaw_sigma(self) -> float:
        """
        yaw one-sigma after the alignment [rad]
        """
    @init_yaw_sigma.setter
    def init_yaw_sigma(self, arg1: typing.Any) -> None:
        ...
    @property
    def lever_arm_b(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[3, 1]"]:
        """
        GPS antenna relative to the IMU, body FRD [m]
        """
    @lever_arm_b.setter
    def lever_arm_b(self, arg1: typing.Any) -> None:
        ...
    @property
    def lever_arm_sigma(self) -> float:
        """
        one-sigma of each lever-arm component [m]
        """
    @lever_arm_sigma.setter
    def lever_arm_sigma(self, arg1: typing.Any) -> None:
        ...
    @property
    def mag_dip_tol(self) -> float:
        """
        reject the magnetometer when its dip differs from the reference by more (0: off) [rad]
        """
    @mag_dip_tol.setter
    def mag_dip_tol(self, arg1: typing.Any) -> None:
        ...
    @property
    def mag_heading_only(self) -> bool:
        """
        the magnetometer corrects the heading only (its tilt terms go into R; false: the full row) [-]
        """
    @mag_heading_only.setter
    def mag_heading_only(self, arg1: typing.Any) -> None:
        ...
    @property
    def mag_heading_sigma(self) -> float:
        """
        one-sigma of a magnetometer heading [rad]
        """
    @mag_heading_sigma.setter
    def mag_heading_sigma(self, arg1: typing.Any) -> None:
        ...
    @property
    def mag_norm_tol(self) -> float:
        """
        reject the magnetometer when ||m|/m_ref - 1| exceeds it (0: off) [1]
        """
    @mag_norm_tol.setter
    def mag_norm_tol(self, arg1: typing.Any) -> None:
        ...
    @property
    def mag_ref_samples(self) -> int:
        """
        magnetometer samples over which the reference norm and dip are averaged [1]
        """
    @mag_ref_samples.setter
    def mag_ref_samples(self, arg1: typing.Any) -> None:
        ...
    @property
    def max_coast(self) -> float:
        """
        longest IMU gap the batch run coasts across (in steps of at most max_dt) [s]
        """
    @max_coast.setter
    def max_coast(self, arg1: typing.Any) -> None:
        ...
    @property
    def max_dt(self) -> float:
        """
        longest accepted IMU step [s]
        """
    @max_dt.setter
    def max_dt(self, arg1: typing.Any) -> None:
        ...
    @property
    def min_speed_for_heading(self) -> float:
        """
        GPS speed above which the heading comes from the GPS track [m/s]
        """
    @min_speed_for_heading.setter
    def min_speed_for_heading(self, arg1: typing.Any) -> None:
        ...
    @property
    def nhc(self) -> bool:
        """
        non-holonomic constraint: no lateral or vertical velocity (wheeled vehicles) [-]
        """
    @nhc.setter
    def nhc(self, arg1: typing.Any) -> None:
        ...
    @property
    def nhc_arm(self) -> float:
        """
        largest distance of the IMU from the non-slipping axle: the constraint's lateral variance gains (w_z nhc_arm)^2 (0: off) [m]
        """
    @nhc_arm.setter
    def nhc_arm(self, arg1: typing.Any) -> None:
        ...
    @property
    def nhc_auto(self) -> bool:
        """
        apply the non-holonomic constraint once the vehicle has shown it: nhc_auto_time s of GNSS-aided motion above nhc_auto_speed with the lateral and vertical body velocity within nhc_auto_limit (RMS); its R is then the larger of nhc_sigma^2 and that mean square [-]
        """
    @nhc_auto.setter
    def nhc_auto(self, arg1: typing.Any) -> None:
        ...
    @property
    def nhc_auto_limit(self) -> float:
        """
        non-holonomic evidence: largest RMS lateral and vertical body velocity (above twice it the evidence is lost) [m/s]
        """
    @nhc_auto_limit.setter
    def nhc_auto_limit(self, arg1: typing.Any) -> None:
        ...
    @property
    def nhc_auto_rate(self) -> float:
        """
        non-holonomic evidence: largest body yaw rate at which the IMU's mounting (its mean lateral and vertical velocity per forward speed) is learned [rad/s]
        """
    @nhc_auto_rate.setter
    def nhc_auto_rate(self, arg1: typing.Any) -> None:
        ...
    @property
    def nhc_auto_speed(self) -> float:
        """
        non-holonomic evidence: slowest speed that counts [m/s]
        """
    @nhc_auto_speed.setter
    def nhc_auto_speed(self, arg1: typing.Any) -> None:
        ...
    @property
    def nhc_auto_time(self) -> float:
        """
        non-holonomic evidence: duration needed (the mean square's time constant is a quarter of it) [s]
        """
    @nhc_auto_time.setter
    def nhc_auto_time(self, arg1: typing.Any) -> None:
        ...
    @property
    def nhc_lateral_aided(self) -> bool:
        """
        apply the learned non-holonomic constraint's lateral row while GNSS-aided too (default: in outages only; its mounting yaw is learned from the aided heading) [-]
        """
    @nhc_lateral_aided.setter
    def nhc_lateral_aided(self, arg1: typing.Any) -> None:
        ...
    @property
    def nhc_lever_b(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[3, 1]"]:
        """
        the non-slipping point (the middle of the rear axle) relative to the IMU, body FRD: the constraint holds the velocity there, v_b + w x nhc_lever_b [m]
        """
    @nhc_lever_b.setter
    def nhc_lever_b(self, arg1: typing.Any) -> None:
        ...
    @property
    def nhc_mount_tau_pitch(self) -> float:
        """
        time constant over which the IMU's mounting in pitch (vertical velocity per forward speed) is learned from straight GNSS-aided driving (0: not learned) [s]
        """
    @nhc_mount_tau_pitch.setter
    def nhc_mount_tau_pitch(self, arg1: typing.Any) -> None:
        ...
    @property
    def nhc_mount_tau_yaw(self) -> float:
        """
        time constant over which the IMU's mounting in yaw (lateral velocity per forward speed) is learned from straight GNSS-aided driving (0: not learned) [s]
        """
    @nhc_mount_tau_yaw.setter
    def nhc_mount_tau_yaw(self, arg1: typing.Any) -> None:
        ...
    @property
    def nhc_sigma(self) -> float:
        """
        one-sigma of the lateral and vertical body velocity [m/s]
        """
    @nhc_sigma.setter
    def nhc_sigma(self, arg1: typing.Any) -> None:
        ...
    @property
    def odometer_sigma(self) -> float:
        """
        one-sigma of an odometer speed [m/s]
        """
    @odometer_sigma.setter
    def odometer_sigma(self, arg1: typing.Any) -> None:
        ...
    @property
    def pseudo_interval(self) -> float:
        """
        shortest interval between two zero-velocity or non-holonomic updates [s]
        """
    @pseudo_interval.setter
    def pseudo_interval(self, arg1: typing.Any) -> None:
        ...
    @property
    def rest_acc_th(self) -> float:
        """
        rest: largest deviation of the accelerometer from its low-pass and of its norm from gravity [m/s^2]
        """
    @rest_acc_th.setter
    def rest_acc_th(self, arg1: typing.Any) -> None:
        ...
    @property
    def rest_gyr_th(self) -> float:
        """
        rest: largest deviation of the gyro from its low-pass [rad/s]
        """
    @rest_gyr_th.setter
    def rest_gyr_th(self, arg1: typing.Any) -> None:
        ...
    @property
    def rest_speed(self) -> float:
        """
        rest: largest speed (the GNSS's before navigation; during it the INS's, plus three sigma up to this value again) [m/s]
        """
    @rest_speed.setter
    def rest_speed(self, arg1: typing.Any) -> None:
        ...
    @property
    def rest_tau(self) -> float:
        """
        rest: low-pass time constant [s]
        """
    @rest_tau.setter
    def rest_tau(self, arg1: typing.Any) -> None:
        ...
    @property
    def rest_time(self) -> float:
        """
        rest: shortest duration [s]
        """
    @rest_time.setter
    def rest_time(self, arg1: typing.Any) -> None:
        ...
    @property
    def zaru_sigma(self) -> float:
        """
        one-sigma of the angular rate at rest beyond the gyro's white noise [rad/s]
        """
    @zaru_sigma.setter
    def zaru_sigma(self, arg1: typing.Any) -> None:
        ...
    @property
    def zupt(self) -> bool:
        """
        zero-velocity and zero-angular-rate updates at rest [-]
        """
    @zupt.setter
    def zupt(self, arg1: typing.Any) -> None:
        ...
    @property
    def zupt_sigma(self) -> float:
        """
        one-sigma of the velocity at rest [m/s]
        """
    @zupt_sigma.setter
    def zupt_sigma(self, arg1: typing.Any) -> None:
        ...
class GpsInsFilter_f64:
    @staticmethod
    def state_fields() -> list:
        """
        The state's declaration table: (name, default, unit, doc).
        """
    def __init__(self, params: GpsInsParams_f64) -> None:
        ...
    def clear(self) -> None:
        """
        Back to the start of alignment (parameters kept).
        """
    def get_state(self) -> dict:
        """
        The complete state as a dict of arrays and numbers (set_state restores it exactly).
        """
    def predict(self, omega_ib_b: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], f_ib_b: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], dt: typing.SupportsFloat | typing.SupportsIndex) -> str:
        ...
    def reset(self, q_nb: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[4, 1]"], v_n: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], lat: typing.SupportsFloat | typing.SupportsIndex, lon: typing.SupportsFloat | typing.SupportsIndex, h: typing.SupportsFloat | typing.SupportsIndex, acc_bias: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], gyro_bias: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], P: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[16, 16]"]) -> str:
        ...
    def run(self, t: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], gyro: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], accel: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], mag: typing.Any, increments: bool, gps_t: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], gps_llh: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], gps_vel: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], gps_pos_sigma: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], gps_vel_sigma: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], baro_t: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], baro_h: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], compass_t: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], compass_yaw: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], odo_t: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], odo_speed: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], smooth: bool = False, segment: typing.SupportsInt | typing.SupportsIndex = 256, gps_solution: typing.Any = None) -> dict:
        """
        Batch run in C++ with the GIL released (see quatnav::gpsins_batch). Returns a dict of arrays; each aid's report is a dict (innovation, nis, status, decision, inflation). With smooth, also 'smoothed': the Rauch-Tung-Striebel estimates (llh, v_n, q_nb, acc_bias, gyro_bias, sigma, baro_offset; acc_scale, gyro_scale with the scale-factor states) and the smoother's 'info' (nav/gps_ins/smoother.hpp).
        """
    def set_initial(self, q_nb: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[4, 1]"], v_n: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], v_valid: bool, acc_bias: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], gyro_bias: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"]) -> str:
        ...
    def set_params(self, params: GpsInsParams_f64) -> None:
        ...
    def set_state(self, state: dict) -> str:
        """
        Restore a state from get_state(); unknown and missing keys are refused.
        """
    def update_baro(self, h: typing.SupportsFloat | typing.SupportsIndex) -> tuple[GpsInsUpdate1_f64, GpsInsUpdate1_f64]:
        ...
    def update_compass(self, heading: typing.SupportsFloat | typing.SupportsIndex) -> GpsInsUpdate1_f64:
        ...
    def update_constraints(self) -> tuple[GpsInsUpdate3_f64, GpsInsUpdate3_f64, GpsInsUpdate2_f64]:
        ...
    def update_gps(self, lat: typing.SupportsFloat | typing.SupportsIndex, lon: typing.SupportsFloat | typing.SupportsIndex, h: typing.SupportsFloat | typing.SupportsIndex, v_n: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], pos_sigma: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], vel_sigma: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], age: typing.SupportsFloat | typing.SupportsIndex = 0.0, solution: typing.SupportsInt | typing.SupportsIndex = 0) -> tuple[GpsInsUpdate3_f64, GpsInsUpdate3_f64]:
        ...
    def update_gps_position(self, lat: typing.SupportsFloat | typing.SupportsIndex, lon: typing.SupportsFloat | typing.SupportsIndex, h: typing.SupportsFloat | typing.SupportsIndex, sigma: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], age: typing.SupportsFloat | typing.SupportsIndex = 0.0, solution: typing.SupportsInt | typing.SupportsIndex = 0) -> GpsInsUpdate3_f64:
        ...
    def update_gps_velocity(self, v_n: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], sigma: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], age: typing.SupportsFloat | typing.SupportsIndex = 0.0) -> GpsInsUpdate3_f64:
        ...
    def update_mag(self, m: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"]) -> GpsInsUpdate1_f64:
        ...
    def update_odometer(self, speed: typing.SupportsFloat | typing.SupportsIndex) -> GpsInsUpdate1_f64:
        ...
    @property
    def acc_bias(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[3, 1]"]:
        ...
    @property
    def acc_scale(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[3, 1]"]:
        ...
    @property
    def align_method(self) -> str:
        ...
    @property
    def at_rest(self) -> bool:
        ...
    @property
    def baro_offset(self) -> float:
        ...
    @property
    def counters(self) -> dict:
        ...
    @property
    def covariance(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[16, 16]"]:
        ...
    @property
    def gyro_bias(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[3, 1]"]:
        ...
    @property
    def gyro_scale(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[3, 1]"]:
        ...
    @property
    def heading_source(self) -> str:
        ...
    @property
    def llh(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[3, 1]"]:
        ...
    @property
    def n_states(self) -> int:
        ...
    @property
    def navigating(self) -> bool:
        ...
    @property
    def params(self) -> GpsInsParams_f64:
        ...
    @property
    def phase(self) -> int:
        ...
    @property
    def q_nb(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[4, 1]"]:
        ...
    @property
    def q_scale(self) -> float:
        ...
    @property
    def time(self) -> float:
        ...
    @property
    def v_n(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[3, 1]"]:
        ...
class GpsInsUpdate1_f32:
    """
    Outcome of one GpsInsFilter update: status, innovation (INS minus aid), its covariance, NIS, decision (code, see decision_names()), inflation.
    """
    def __repr__(self) -> str:
        ...
    @property
    def accepted(self) -> bool:
        ...
    @property
    def decision(self) -> int:
        ...
    @property
    def inflation(self) -> float:
        ...
    @property
    def innovation(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float32], "[1, 1]"]:
        ...
    @property
    def innovation_cov(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float32], "[1, 1]"]:
        ...
    @property
    def nis(self) -> float:
        ...
    @property
    def status(self) -> str:
        ...
class GpsInsUpdate2_f32:
    """
    Outcome of one GpsInsFilter update: status, innovation (INS minus aid), its covariance, NIS, decision (code, see decision_names()), inflation.
    """
    def __repr__(self) -> str:
        ...
    @property
    def accepted(self) -> bool:
        ...
    @property
    def decision(self) -> int:
        ...
    @property
    def inflation(self) -> float:
        ...
    @property
    def innovation(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float32], "[2, 1]"]:
        ...
    @property
    def innovation_cov(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float32], "[2, 2]"]:
        ...
    @property
    def nis(self) -> float:
        ...
    @property
    def status(self) -> str:
        ...
class GpsInsUpdate3_f32:
    """
    Outcome of one GpsInsFilter update: status, innovation (INS minus aid), its covariance, NIS, decision (code, see decision_names()), inflation.
    """
    def __repr__(self) -> str:
        ...
    @property
    def accepted(self) -> bool:
        ...
    @property
    def decision(self) -> int:
        ...
    @property
    def inflation(self) -> float:
        ...
    @property
    def innovation(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float32], "[3, 1]"]:
        ...
    @property
    def innovation_cov(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float32], "[3, 3]"]:
        ...
    @property
    def nis(self) -> float:
        ...
    @property
    def status(self) -> str:
        ...
class GpsInsParams_f32:
    """
    Parameters of GpsInsFilter (nav/gps_ins/params.hpp).
    """
    @staticmethod
    def fields() -> list:
        """
        The declaration table: a list of (name, default, unit, doc).
        """
    @staticmethod
    def from_dict(d: dict) -> GpsInsParams_f32:
        """
        From a dict of some fields (the others keep their defaults); unknown keys refused.
        """
    def __init__(self) -> None:
        ...
    def __repr__(self) -> str:
        ...
    def to_dict(self) -> dict:
        ...
    @property
    def acc_bias_noise(self) -> float:
        """
        accelerometer-bias random-walk density [m/s^3/sqrt(Hz)]
        """
    @acc_bias_noise.setter
    def acc_bias_noise(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_bias_tau(self) -> float:
        """
        Gauss-Markov time constant of the accelerometer bias (0: random walk) [s]
        """
    @acc_bias_tau.setter
    def acc_bias_tau(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_noise(self) -> float:
        """
        accelerometer white-noise density (velocity random walk) [m/s^2/sqrt(Hz)]
        """
    @acc_noise.setter
    def acc_noise(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_range(self) -> float:
        """
        accelerometer range per axis, as gyro_range (0: unlimited) [m/s^2]
        """
    @acc_range.setter
    def acc_range(self, arg1: typing.Any) -> None:
        ...
    @property
    def acc_scale_noise(self) -> float:
        """
        accelerometer scale-factor random-walk density (scale-factor states only) [1/sqrt(s)]
        """
    @acc_scale_noise.setter
    def acc_scale_noise(self, arg1: typing.Any) -> None:
        ...
    @property
    def adapt_gain(self) -> float:
        """
        step of the adaptation per GNSS update (natural log of the scale) [1]
        """
    @adapt_gain.setter
    def adapt_gain(self, arg1: typing.Any) -> None:
        ...
    @property
    def adapt_q_max(self) -> float:
        """
        largest process-noise scale of the innovation-based adaptation (1: off) [1]
        """
    @adapt_q_max.setter
    def adapt_q_max(self, arg1: typing.Any) -> None:
        ...
    @property
    def align_course_distance(self) -> float:
        """
        distance between the position fixes whose course gives the heading (position-only GNSS) [m]
        """
    @align_course_distance.setter
    def align_course_distance(self, arg1: typing.Any) -> None:
        ...
    @property
    def align_level_sigma(self) -> float:
        """
        roll/pitch one-sigma after an alignment in motion without GNSS velocity [rad]
        """
    @align_level_sigma.setter
    def align_level_sigma(self, arg1: typing.Any) -> None:
        ...
    @property
    def align_motion_max(self) -> float:
        """
        longest window of an alignment in motion (then it restarts) [s]
        """
    @align_motion_max.setter
    def align_motion_max(self, arg1: typing.Any) -> None:
        ...
    @property
    def align_motion_time(self) -> float:
        """
        shortest window of an alignment in motion [s]
        """
    @align_motion_time.setter
    def align_motion_time(self, arg1: typing.Any) -> None:
        ...
    @property
    def align_time(self) -> float:
        """
        duration of the static alignment (still samples; motion restarts it) [s]
        """
    @align_time.setter
    def align_time(self, arg1: typing.Any) -> None:
        ...
    @property
    def baro_offset_noise(self) -> float:
        """
        random-walk density of the altimeter offset [m/sqrt(s)]
        """
    @baro_offset_noise.setter
    def baro_offset_noise(self, arg1: typing.Any) -> None:
        ...
    @property
    def baro_rate_baseline(self) -> float:
        """
        baseline of the altimeter's vertical-velocity difference [s]
        """
    @baro_rate_baseline.setter
    def baro_rate_baseline(self, arg1: typing.Any) -> None:
        ...
    @property
    def baro_sigma(self) -> float:
        """
        one-sigma of an altimeter height [m]
        """
    @baro_sigma.setter
    def baro_sigma(self, arg1: typing.Any) -> None:
        ...
    @property
    def baro_vd_sigma(self) -> float:
        """
        one-sigma of the altimeter's vertical velocity [m/s]
        """
    @baro_vd_sigma.setter
    def baro_vd_sigma(self, arg1: typing.Any) -> None:
        ...
    @property
    def compass_sigma(self) -> float:
        """
        one-sigma of a compass heading [rad]
        """
    @compass_sigma.setter
    def compass_sigma(self, arg1: typing.Any) -> None:
        ...
    @property
    def cov_floor(self) -> float:
        """
        eigenvalue floor of the error covariance (0: off) [state units^2]
        """
    @cov_floor.setter
    def cov_floor(self, arg1: typing.Any) -> None:
        ...
    @property
    def declination(self) -> float:
        """
        magnetic declination, east of true north (added to compass headings) [rad]
        """
    @declination.setter
    def declination(self, arg1: typing.Any) -> None:
        ...
    @property
    def earth_rotation(self) -> bool:
        """
        include the Earth rate, transport rate and Coriolis terms [-]
        """
    @earth_rotation.setter
    def earth_rotation(self, arg1: typing.Any) -> None:
        ...
    @property
    def gate_baro(self) -> float:
        """
        NIS gate of the altimeter (0: off) [1 (chi-square, 1 dof)]
        """
    @gate_baro.setter
    def gate_baro(self, arg1: typing.Any) -> None:
        ...
    @property
    def gate_compass(self) -> float:
        """
        NIS gate of the compass (0: off) [1 (chi-square, 1 dof)]
        """
    @gate_compass.setter
    def gate_compass(self, arg1: typing.Any) -> None:
        ...
    @property
    def gate_gps_pos(self) -> float:
        """
        NIS gate of the GPS position (0: off) [1 (chi-square, 3 dof)]
        """
    @gate_gps_pos.setter
    def gate_gps_pos(self, arg1: typing.Any) -> None:
        ...
    @property
    def gate_gps_vel(self) -> float:
        """
        NIS gate of the GPS velocity (0: off) [1 (chi-square, 3 dof)]
        """
    @gate_gps_vel.setter
    def gate_gps_vel(self, arg1: typing.Any) -> None:
        ...
    @property
    def gate_mag(self) -> float:
        """
        NIS gate of the magnetometer heading (0: off) [1 (chi-square, 1 dof)]
        """
    @gate_mag.setter
    def gate_mag(self, arg1: typing.Any) -> None:
        ...
    @property
    def gate_nhc(self) -> float:
        """
        NIS gate of the non-holonomic constraint (0: off) [1 (chi-square, 2 dof)]
        """
    @gate_nhc.setter
    def gate_nhc(self, arg1: typing.Any) -> None:
        ...
    @property
    def gate_odometer(self) -> float:
        """
        NIS gate of the odometer (0: off) [1 (chi-square, 1 dof)]
        """
    @gate_odometer.setter
    def gate_odometer(self, arg1: typing.Any) -> None:
        ...
    @property
    def gate_zupt(self) -> float:
        """
        NIS gate of the zero-velocity and zero-rate updates (0: off) [1 (chi-square, 3 dof)]
        """
    @gate_zupt.setter
    def gate_zupt(self, arg1: typing.Any) -> None:
        ...
    @property
    def gps_dgnss_sigma_min(self) -> float:
        """
        floor of a GPS position one-sigma of a DGNSS, SBAS or PPP solution [m]
        """
    @gps_dgnss_sigma_min.setter
    def gps_dgnss_sigma_min(self, arg1: typing.Any) -> None:
        ...
    @property
    def gps_error_tau(self) -> float:
        """
        correlation time of the position errors of RTK-float, DGNSS and single solutions (0: white) [s]
        """
    @gps_error_tau.setter
    def gps_error_tau(self, arg1: typing.Any) -> None:
        ...
    @property
    def gps_float_sigma_min(self) -> float:
        """
        floor of a GPS position one-sigma of an RTK-float solution [m]
        """
    @gps_float_sigma_min.setter
    def gps_float_sigma_min(self, arg1: typing.Any) -> None:
        ...
    @property
    def gps_pos_sigma_h(self) -> float:
        """
        horizontal one-sigma of a GPS position (per-fix sigma overrides) [m]
        """
    @gps_pos_sigma_h.setter
    def gps_pos_sigma_h(self, arg1: typing.Any) -> None:
        ...
    @property
    def gps_pos_sigma_min(self) -> float:
        """
        floor of a GPS position one-sigma (given or per fix) of an RTK-fixed solution or one of unknown kind [m]
        """
    @gps_pos_sigma_min.setter
    def gps_pos_sigma_min(self, arg1: typing.Any) -> None:
        ...
    @property
    def gps_pos_sigma_v(self) -> float:
        """
        vertical one-sigma of a GPS position [m]
        """
    @gps_pos_sigma_v.setter
    def gps_pos_sigma_v(self, arg1: typing.Any) -> None:
        ...
    @property
    def gps_robust_k(self) -> float:
        """
        Huber threshold of the GNSS aids: an innovation component beyond it (in its sigmas) is down-weighted (0: off) [1]
        """
    @gps_robust_k.setter
    def gps_robust_k(self, arg1: typing.Any) -> None:
        ...
    @property
    def gps_single_sigma_min(self) -> float:
        """
        floor of a GPS position one-sigma of a single (standalone) solution [m]
        """
    @gps_single_sigma_min.setter
    def gps_single_sigma_min(self, arg1: typing.Any) -> None:
        ...
    @property
    def gps_time_offset(self) -> float:
        """
        added to the GNSS times to put them on the IMU clock (a receiver latency L: -L) [s]
        """
    @gps_time_offset.setter
    def gps_time_offset(self, arg1: typing.Any) -> None:
        ...
    @property
    def gps_time_sigma(self) -> float:
        """
        one-sigma of the GNSS time on the IMU clock [s]
        """
    @gps_time_sigma.setter
    def gps_time_sigma(self, arg1: typing.Any) -> None:
        ...
    @property
    def gps_vel_sigma(self) -> float:
        """
        one-sigma of each GPS velocity component [m/s]
        """
    @gps_vel_sigma.setter
    def gps_vel_sigma(self, arg1: typing.Any) -> None:
        ...
    @property
    def gps_vel_sigma_min(self) -> float:
        """
        floor of a GPS velocity one-sigma (given or per fix) [m/s]
        """
    @gps_vel_sigma_min.setter
    def gps_vel_sigma_min(self, arg1: typing.Any) -> None:
        ...
    @property
    def gps_vertical_floor_ratio(self) -> float:
        """
        floor of a GPS position's down one-sigma over the north and east floor of its solution kind [1]
        """
    @gps_vertical_floor_ratio.setter
    def gps_vertical_floor_ratio(self, arg1: typing.Any) -> None:
        ...
    @property
    def gyro_bias_noise(self) -> float:
        """
        gyro-bias random-walk density [rad/s^2/sqrt(Hz)]
        """
    @gyro_bias_noise.setter
    def gyro_bias_noise(self, arg1: typing.Any) -> None:
        ...
    @property
    def gyro_bias_tau(self) -> float:
        """
        Gauss-Markov time constant of the gyro bias (0: random walk) [s]
        """
    @gyro_bias_tau.setter
    def gyro_bias_tau(self, arg1: typing.Any) -> None:
        ...
    @property
    def gyro_noise(self) -> float:
        """
        gyro white-noise density (angle random walk) [rad/s/sqrt(Hz)]
        """
    @gyro_noise.setter
    def gyro_noise(self, arg1: typing.Any) -> None:
        ...
    @property
    def gyro_range(self) -> float:
        """
        gyro range per axis: a reading at or above it is saturated and its step skipped (0: unlimited) [rad/s]
        """
    @gyro_range.setter
    def gyro_range(self, arg1: typing.Any) -> None:
        ...
    @property
    def gyro_rate_noise(self) -> float:
        """
        rate-proportional attitude process noise: density gyro_rate_noise * |w - b| (0: off); the attitude filters apply it to the tilt only [1/sqrt(Hz)]
        """
    @gyro_rate_noise.setter
    def gyro_rate_noise(self, arg1: typing.Any) -> None:
        ...
    @property
    def gyro_scale_noise(self) -> float:
        """
        gyro scale-factor random-walk density (scale-factor states only) [1/sqrt(s)]
        """
    @gyro_scale_noise.setter
    def gyro_scale_noise(self, arg1: typing.Any) -> None:
        ...
    @property
    def heading_from_gps(self) -> bool:
        """
        initialize the heading from the GPS track (without compass) [-]
        """
    @heading_from_gps.setter
    def heading_from_gps(self, arg1: typing.Any) -> None:
        ...
    @property
    def imu_rotation(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float32], "[3, 3]"]:
        """
        rotation from the IMU axes to the body axes: body = imu_rotation imu [1]
        """
    @imu_rotation.setter
    def imu_rotation(self, arg1: typing.Any) -> None:
        ...
    @property
    def inflate_after(self) -> float:
        """
        consecutive gate rejections of a GNSS aid after which the next failing fix inflates the covariance (0: never) [1]
        """
    @inflate_after.setter
    def inflate_after(self, arg1: typing.Any) -> None:
        ...
    @property
    def inflate_max(self) -> float:
        """
        largest covariance inflation; a fix that needs more resets the state to it [1]
        """
    @inflate_max.setter
    def inflate_max(self, arg1: typing.Any) -> None:
        ...
    @property
    def init_acc_bias_sigma(self) -> float:
        """
        accelerometer-bias one-sigma at the start of navigation [m/s^2]
        """
    @init_acc_bias_sigma.setter
    def init_acc_bias_sigma(self, arg1: typing.Any) -> None:
        ...
    @property
    def init_acc_scale_sigma(self) -> float:
        """
        accelerometer scale-factor one-sigma at the start of navigation (scale-factor states only) [1]
        """
    @init_acc_scale_sigma.setter
    def init_acc_scale_sigma(self, arg1: typing.Any) -> None:
        ...
    @property
    def init_gyro_bias_sigma(self) -> float:
        """
        gyro-bias one-sigma at the start of navigation [rad/s]
        """
    @init_gyro_bias_sigma.setter
    def init_gyro_bias_sigma(self, arg1: typing.Any) -> None:
        ...
    @property
    def init_gyro_scale_sigma(self) -> float:
        """
        gyro scale-factor one-sigma at the start of navigation (scale-factor states only) [1]
        """
    @init_gyro_scale_sigma.setter
    def init_gyro_scale_sigma(self, arg1: typing.Any) -> None:
        ...
    @property
    def init_level_sigma(self) -> float:
        """
        roll/pitch one-sigma after the alignment [rad]
        """
    @init_level_sigma.setter
    def init_level_sigma(self, arg1: typing.Any) -> None:
        ...
    @property
    def init_vel_sigma(self) -> float:
        """
        velocity one-sigma at the start of navigation [m/s]
        """
    @init_vel_sigma.setter
    def init_vel_sigma(self, arg1: typing.Any) -> None:
        ...
    @property
    def init_yaw_sigma(self) -> float:
        """
        yaw one-sigma after the alignment [rad]
        """
    @init_yaw_sigma.setter
    def init_yaw_sigma(self, arg1: typing.Any) -> None:
        ...
    @property
    def lever_arm_b(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float32], "[3, 1]"]:
        """
        GPS antenna relative to the IMU, body FRD [m]
        """
    @lever_arm_b.setter
    def lever_arm_b(self, arg1: typing.Any) -> None:
        ...
    @property
    def lever_arm_sigma(self) -> float:
        """
        one-sigma of each lever-arm component [m]
        """
    @lever_arm_sigma.setter
    def lever_arm_sigma(self, arg1: typing.Any) -> None:
        ...
    @property
    def mag_dip_tol(self) -> float:
        """
        reject the magnetometer when its dip differs from the reference by more (0: off) [rad]
        """
    @mag_dip_tol.setter
    def mag_dip_tol(self, arg1: typing.Any) -> None:
        ...
    @property
    def mag_heading_only(self) -> bool:
        """
        the magnetometer corrects the heading only (its tilt terms go into R; false: the full row) [-]
        """
    @mag_heading_only.setter
    def mag_heading_only(self, arg1: typing.Any) -> None:
        ...
    @property
    def mag_heading_sigma(self) -> float:
        """
        one-sigma of a magnetometer heading [rad]
        """
    @mag_heading_sigma.setter
    def mag_heading_sigma(self, arg1: typing.Any) -> None:
        ...
    @property
    def mag_norm_tol(self) -> float:
        """
        reject the magnetometer when ||m|/m_ref - 1| exceeds it (0: off) [1]
        """
    @mag_norm_tol.setter
    def mag_norm_tol(self, arg1: typing.Any) -> None:
        ...
    @property
    def mag_ref_samples(self) -> int:
        """
        magnetometer samples over which the reference norm and dip are averaged [1]
        """
    @mag_ref_samples.setter
    def mag_ref_samples(self, arg1: typing.Any) -> None:
        ...
    @property
    def max_coast(self) -> float:
        """
        longest IMU gap the batch run coasts across (in steps of at most max_dt) [s]
        """
    @max_coast.setter
    def max_coast(self, arg1: typing.Any) -> None:
        ...
    @property
    def max_dt(self) -> float:
        """
        longest accepted IMU step [s]
        """
    @max_dt.setter
    def max_dt(self, arg1: typing.Any) -> None:
        ...
    @property
    def min_speed_for_heading(self) -> float:
        """
        GPS speed above which the heading comes from the GPS track [m/s]
        """
    @min_speed_for_heading.setter
    def min_speed_for_heading(self, arg1: typing.Any) -> None:
        ...
    @property
    def nhc(self) -> bool:
        """
        non-holonomic constraint: no lateral or vertical velocity (wheeled vehicles) [-]
        """
    @nhc.setter
    def nhc(self, arg1: typing.Any) -> None:
        ...
    @property
    def nhc_arm(self) -> float:
        """
        largest distance of the IMU from the non-slipping axle: the constraint's lateral variance gains (w_z nhc_arm)^2 (0: off) [m]
        """
    @nhc_arm.setter
    def nhc_arm(self, arg1: typing.Any) -> None:
        ...
    @property
    def nhc_auto(self) -> bool:
        """
        apply the non-holonomic constraint once the vehicle has shown it: nhc_auto_time s of GNSS-aided motion above nhc_auto_speed with the lateral and vertical body velocity within nhc_auto_limit (RMS); its R is then the larger of nhc_sigma^2 and that mean square [-]
        """
    @nhc_auto.setter
    def nhc_auto(self, arg1: typing.Any) -> None:
        ...
    @property
    def nhc_auto_limit(self) -> float:
        """
        non-holonomic evidence: largest RMS lateral and vertical body velocity (above twice it the evidence is lost) [m/s]
        """
    @nhc_auto_limit.setter
    def nhc_auto_limit(self, arg1: typing.Any) -> None:
        ...
    @property
    def nhc_auto_rate(self) -> float:
        """
        non-holonomic evidence: largest body yaw rate at which the IMU's mounting (its mean lateral and vertical velocity per forward speed) is learned [rad/s]
        """
    @nhc_auto_rate.setter
    def nhc_auto_rate(self, arg1: typing.Any) -> None:
        ...
    @property
    def nhc_auto_speed(self) -> float:
        """
        non-holonomic evidence: slowest speed that counts [m/s]
        """
    @nhc_auto_speed.setter
    def nhc_auto_speed(self, arg1: typing.Any) -> None:
        ...
    @property
    def nhc_auto_time(self) -> float:
        """
        non-holonomic evidence: duration needed (the mean square's time constant is a quarter of it) [s]
        """
    @nhc_auto_time.setter
    def nhc_auto_time(self, arg1: typing.Any) -> None:
        ...
    @property
    def nhc_lateral_aided(self) -> bool:
        """
        apply the learned non-holonomic constraint's lateral row while GNSS-aided too (default: in outages only; its mounting yaw is learned from the aided heading) [-]
        """
    @nhc_lateral_aided.setter
    def nhc_lateral_aided(self, arg1: typing.Any) -> None:
        ...
    @property
    def nhc_lever_b(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float32], "[3, 1]"]:
        """
        the non-slipping point (the middle of the rear axle) relative to the IMU, body FRD: the constraint holds the velocity there, v_b + w x nhc_lever_b [m]
        """
    @nhc_lever_b.setter
    def nhc_lever_b(self, arg1: typing.Any) -> None:
        ...
    @property
    def nhc_mount_tau_pitch(self) -> float:
        """
        time constant over which the IMU's mounting in pitch (vertical velocity per forward speed) is learned from straight GNSS-aided driving (0: not learned) [s]
        """
    @nhc_mount_tau_pitch.setter
    def nhc_mount_tau_pitch(self, arg1: typing.Any) -> None:
        ...
    @property
    def nhc_mount_tau_yaw(self) -> float:
        """
        time constant over which the IMU's mounting in yaw (lateral velocity per forward speed) is learned from straight GNSS-aided driving (0: not learned) [s]
        """
    @nhc_mount_tau_yaw.setter
    def nhc_mount_tau_yaw(self, arg1: typing.Any) -> None:
        ...
    @property
    def nhc_sigma(self) -> float:
        """
        one-sigma of the lateral and vertical body velocity [m/s]
        """
    @nhc_sigma.setter
    def nhc_sigma(self, arg1: typing.Any) -> None:
        ...
    @property
    def odometer_sigma(self) -> float:
        """
        one-sigma of an odometer speed [m/s]
        """
    @odometer_sigma.setter
    def odometer_sigma(self, arg1: typing.Any) -> None:
        ...
    @property
    def pseudo_interval(self) -> float:
        """
        shortest interval between two zero-velocity or non-holonomic updates [s]
        """
    @pseudo_interval.setter
    def pseudo_interval(self, arg1: typing.Any) -> None:
        ...
    @property
    def rest_acc_th(self) -> float:
        """
        rest: largest deviation of the accelerometer from its low-pass and of its norm from gravity [m/s^2]
        """
    @rest_acc_th.setter
    def rest_acc_th(self, arg1: typing.Any) -> None:
        ...
    @property
    def rest_gyr_th(self) -> float:
        """
        rest: largest deviation of the gyro from its low-pass [rad/s]
        """
    @rest_gyr_th.setter
    def rest_gyr_th(self, arg1: typing.Any) -> None:
        ...
    @property
    def rest_speed(self) -> float:
        """
        rest: largest speed (the GNSS's before navigation; during it the INS's, plus three sigma up to this value again) [m/s]
        """
    @rest_speed.setter
    def rest_speed(self, arg1: typing.Any) -> None:
        ...
    @property
    def rest_tau(self) -> float:
        """
        rest: low-pass time constant [s]
        """
    @rest_tau.setter
    def rest_tau(self, arg1: typing.Any) -> None:
        ...
    @property
    def rest_time(self) -> float:
        """
        rest: shortest duration [s]
        """
    @rest_time.setter
    def rest_time(self, arg1: typing.Any) -> None:
        ...
    @property
    def zaru_sigma(self) -> float:
        """
        one-sigma of the angular rate at rest beyond the gyro's white noise [rad/s]
        """
    @zaru_sigma.setter
    def zaru_sigma(self, arg1: typing.Any) -> None:
        ...
    @property
    def zupt(self) -> bool:
        """
        zero-velocity and zero-angular-rate updates at rest [-]
        """
    @zupt.setter
    def zupt(self, arg1: typing.Any) -> None:
        ...
    @property
    def zupt_sigma(self) -> float:
        """
        one-sigma of the velocity at rest [m/s]
        """
    @zupt_sigma.setter
    def zupt_sigma(self, arg1: typing.Any) -> None:
        ...
class GpsInsFilter_f32:
    @staticmethod
    def state_fields() -> list:
        """
        The state's declaration table: (name, default, unit, doc).
        """
    def __init__(self, params: GpsInsParams_f32) -> None:
        ...
    def clear(self) -> None:
        """
        Back to the start of alignment (parameters kept).
        """
    def get_state(self) -> dict:
        """
        The complete state as a dict of arrays and numbers (set_state restores it exactly).
        """
    def predict(self, omega_ib_b: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], f_ib_b: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], dt: typing.SupportsFloat | typing.SupportsIndex) -> str:
        ...
    def reset(self, q_nb: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[4, 1]"], v_n: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], lat: typing.SupportsFloat | typing.SupportsIndex, lon: typing.SupportsFloat | typing.SupportsIndex, h: typing.SupportsFloat | typing.SupportsIndex, acc_bias: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], gyro_bias: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], P: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[16, 16]"]) -> str:
        ...
    def run(self, t: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], gyro: typing.Annotated[numpy.typing.ArrayLike, numpy.float32], accel: typing.Annotated[numpy.typing.ArrayLike, numpy.float32], mag: typing.Any, increments: bool, gps_t: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], gps_llh: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], gps_vel: typing.Annotated[numpy.typing.ArrayLike, numpy.float32], gps_pos_sigma: typing.Annotated[numpy.typing.ArrayLike, numpy.float32], gps_vel_sigma: typing.Annotated[numpy.typing.ArrayLike, numpy.float32], baro_t: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], baro_h: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], compass_t: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], compass_yaw: typing.Annotated[numpy.typing.ArrayLike, numpy.float32], odo_t: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], odo_speed: typing.Annotated[numpy.typing.ArrayLike, numpy.float32], smooth: bool = False, segment: typing.SupportsInt | typing.SupportsIndex = 256, gps_solution: typing.Any = None) -> dict:
        """
        Batch run in C++ with the GIL released (see quatnav::gpsins_batch). Returns a dict of arrays; each aid's report is a dict (innovation, nis, status, decision, inflation). With smooth, also 'smoothed': the Rauch-Tung-Striebel estimates (llh, v_n, q_nb, acc_bias, gyro_bias, sigma, baro_offset; acc_scale, gyro_scale with the scale-factor states) and the smoother's 'info' (nav/gps_ins/smoother.hpp).
        """
    def set_initial(self, q_nb: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[4, 1]"], v_n: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], v_valid: bool, acc_bias: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], gyro_bias: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"]) -> str:
        ...
    def set_params(self, params: GpsInsParams_f32) -> None:
        ...
    def set_state(self, state: dict) -> str:
        """
        Restore a state from get_state(); unknown and missing keys are refused.
        """
    def update_baro(self, h: typing.SupportsFloat | typing.SupportsIndex) -> tuple[GpsInsUpdate1_f32, GpsInsUpdate1_f32]:
        ...
    def update_compass(self, heading: typing.SupportsFloat | typing.SupportsIndex) -> GpsInsUpdate1_f32:
        ...
    def update_constraints(self) -> tuple[GpsInsUpdate3_f32, GpsInsUpdate3_f32, GpsInsUpdate2_f32]:
        ...
    def update_gps(self, lat: typing.SupportsFloat | typing.SupportsIndex, lon: typing.SupportsFloat | typing.SupportsIndex, h: typing.SupportsFloat | typing.SupportsIndex, v_n: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], pos_sigma: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], vel_sigma: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], age: typing.SupportsFloat | typing.SupportsIndex = 0.0, solution: typing.SupportsInt | typing.SupportsIndex = 0) -> tuple[GpsInsUpdate3_f32, GpsInsUpdate3_f32]:
        ...
    def update_gps_position(self, lat: typing.SupportsFloat | typing.SupportsIndex, lon: typing.SupportsFloat | typing.SupportsIndex, h: typing.SupportsFloat | typing.SupportsIndex, sigma: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], age: typing.SupportsFloat | typing.SupportsIndex = 0.0, solution: typing.SupportsInt | typing.SupportsIndex = 0) -> GpsInsUpdate3_f32:
        ...
    def update_gps_velocity(self, v_n: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], sigma: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], age: typing.SupportsFloat | typing.SupportsIndex = 0.0) -> GpsInsUpdate3_f32:
        ...
    def update_mag(self, m: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"]) -> GpsInsUpdate1_f32:
        ...
    def update_odometer(self, speed: typing.SupportsFloat | typing.SupportsIndex) -> GpsInsUpdate1_f32:
        ...
    @property
    def acc_bias(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float32], "[3, 1]"]:
        ...
    @property
    def acc_scale(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float32], "[3, 1]"]:
        ...
    @property
    def align_method(self) -> str:
        ...
    @property
    def at_rest(self) -> bool:
        ...
    @property
    def baro_offset(self) -> float:
        ...
    @property
    def counters(self) -> dict:
        ...
    @property
    def covariance(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float32], "[16, 16]"]:
        ...
    @property
    def gyro_bias(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float32], "[3, 1]"]:
        ...
    @property
    def gyro_scale(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float32], "[3, 1]"]:
        ...
    @property
    def heading_source(self) -> str:
        ...
    @property
    def llh(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[3, 1]"]:
        ...
    @property
    def n_states(self) -> int:
        ...
    @property
    def navigating(self) -> bool:
        ...
    @property
    def params(self) -> GpsInsParams_f32:
        ...
    @property
    def phase(self) -> int:
        ...
    @property
    def q_nb(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float32], "[4, 1]"]:
        ...
    @property
    def q_scale(self) -> float:
        ...
    @property
    def time(self) -> float:
        ...
    @property
    def v_n(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float32], "[3, 1]"]:
        ...
class GpsInsFilterScale_f64:
    @staticmethod
    def state_fields() -> list:
        """
        The state's declaration table: (name, default, unit, doc).
        """
    def __init__(self, params: GpsInsParams_f64) -> None:
        ...
    def clear(self) -> None:
        """
        Back to the start of alignment (parameters kept).
        """
    def get_state(self) -> dict:
        """
        The complete state as a dict of arrays and numbers (set_state restores it exactly).
        """
    def predict(self, omega_ib_b: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], f_ib_b: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], dt: typing.SupportsFloat | typing.SupportsIndex) -> str:
        ...
    def reset(self, q_nb: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[4, 1]"], v_n: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], lat: typing.SupportsFloat | typing.SupportsIndex, lon: typing.SupportsFloat | typing.SupportsIndex, h: typing.SupportsFloat | typing.SupportsIndex, acc_bias: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], gyro_bias: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], P: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[22, 22]"]) -> str:
        ...
    def run(self, t: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], gyro: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], accel: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], mag: typing.Any, increments: bool, gps_t: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], gps_llh: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], gps_vel: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], gps_pos_sigma: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], gps_vel_sigma: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], baro_t: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], baro_h: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], compass_t: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], compass_yaw: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], odo_t: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], odo_speed: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], smooth: bool = False, segment: typing.SupportsInt | typing.SupportsIndex = 256, gps_solution: typing.Any = None) -> dict:
        """
        Batch run in C++ with the GIL released (see quatnav::gpsins_batch). Returns a dict of arrays; each aid's report is a dict (innovation, nis, status, decision, inflation). With smooth, also 'smoothed': the Rauch-Tung-Striebel estimates (llh, v_n, q_nb, acc_bias, gyro_bias, sigma, baro_offset; acc_scale, gyro_scale with the scale-factor states) and the smoother's 'info' (nav/gps_ins/smoother.hpp).
        """
    def set_initial(self, q_nb: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[4, 1]"], v_n: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], v_valid: bool, acc_bias: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], gyro_bias: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"]) -> str:
        ...
    def set_params(self, params: GpsInsParams_f64) -> None:
        ...
    def set_state(self, state: dict) -> str:
        """
        Restore a state from get_state(); unknown and missing keys are refused.
        """
    def update_baro(self, h: typing.SupportsFloat | typing.SupportsIndex) -> tuple[GpsInsUpdate1_f64, GpsInsUpdate1_f64]:
        ...
    def update_compass(self, heading: typing.SupportsFloat | typing.SupportsIndex) -> GpsInsUpdate1_f64:
        ...
    def update_constraints(self) -> tuple[GpsInsUpdate3_f64, GpsInsUpdate3_f64, GpsInsUpdate2_f64]:
        ...
    def update_gps(self, lat: typing.SupportsFloat | typing.SupportsIndex, lon: typing.SupportsFloat | typing.SupportsIndex, h: typing.SupportsFloat | typing.SupportsIndex, v_n: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], pos_sigma: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], vel_sigma: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], age: typing.SupportsFloat | typing.SupportsIndex = 0.0, solution: typing.SupportsInt | typing.SupportsIndex = 0) -> tuple[GpsInsUpdate3_f64, GpsInsUpdate3_f64]:
        ...
    def update_gps_position(self, lat: typing.SupportsFloat | typing.SupportsIndex, lon: typing.SupportsFloat | typing.SupportsIndex, h: typing.SupportsFloat | typing.SupportsIndex, sigma: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], age: typing.SupportsFloat | typing.SupportsIndex = 0.0, solution: typing.SupportsInt | typing.SupportsIndex = 0) -> GpsInsUpdate3_f64:
        ...
    def update_gps_velocity(self, v_n: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], sigma: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"], age: typing.SupportsFloat | typing.SupportsIndex = 0.0) -> GpsInsUpdate3_f64:
        ...
    def update_mag(self, m: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[3, 1]"]) -> GpsInsUpdate1_f64:
        ...
    def update_odometer(self, speed: typing.SupportsFloat | typing.SupportsIndex) -> GpsInsUpdate1_f64:
        ...
    @property
    def acc_bias(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[3, 1]"]:
        ...
    @property
    def acc_scale(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[3, 1]"]:
        ...
    @property
    def align_method(self) -> str:
        ...
    @property
    def at_rest(self) -> bool:
        ...
    @property
    def baro_offset(self) -> float:
        ...
    @property
    def counters(self) -> dict:
        ...
    @property
    def covariance(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[22, 22]"]:
        ...
    @property
    def gyro_bias(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[3, 1]"]:
        ...
    @property
    def gyro_scale(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[3, 1]"]:
        ...
    @property
    def heading_source(self) -> str:
        ...
    @property
    def llh(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[3, 1]"]:
        ...
    @property
    def n_states(self) -> int:
        ...
    @property
    def navigating(self) -> bool:
        ...
    @property
    def params(self) -> GpsInsParams_f64:
        ...
    @property
    def phase(self) -> int:
        ...
    @property
    def q_nb(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[4, 1]"]:
        ...
    @property
    def q_scale(self) -> float:
        ...
    @property
    def time(self) -> float:
        ...
    @property
    def v_n(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[3, 1]"]:
        ...
class GpsInsFilterScale_f32:
    @staticmethod
    def state_fields() -> list:
        """
        The state's declaration table: (name, default, unit, doc).
        """
    def __init__(self, params: GpsInsParams_f32) -> None:
        ...
    def clear(self) -> None:
        """
        Back to the start of alignment (parameters kept).
        """
    def get_state(self) -> dict:
        """
        The complete state as a dict of arrays and numbers (set_state restores it exactly).
        """
    def predict(self, omega_ib_b: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], f_ib_b: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], dt: typing.SupportsFloat | typing.SupportsIndex) -> str:
        ...
    def reset(self, q_nb: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[4, 1]"], v_n: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], lat: typing.SupportsFloat | typing.SupportsIndex, lon: typing.SupportsFloat | typing.SupportsIndex, h: typing.SupportsFloat | typing.SupportsIndex, acc_bias: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], gyro_bias: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], P: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[22, 22]"]) -> str:
        ...
    def run(self, t: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], gyro: typing.Annotated[numpy.typing.ArrayLike, numpy.float32], accel: typing.Annotated[numpy.typing.ArrayLike, numpy.float32], mag: typing.Any, increments: bool, gps_t: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], gps_llh: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], gps_vel: typing.Annotated[numpy.typing.ArrayLike, numpy.float32], gps_pos_sigma: typing.Annotated[numpy.typing.ArrayLike, numpy.float32], gps_vel_sigma: typing.Annotated[numpy.typing.ArrayLike, numpy.float32], baro_t: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], baro_h: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], compass_t: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], compass_yaw: typing.Annotated[numpy.typing.ArrayLike, numpy.float32], odo_t: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], odo_speed: typing.Annotated[numpy.typing.ArrayLike, numpy.float32], smooth: bool = False, segment: typing.SupportsInt | typing.SupportsIndex = 256, gps_solution: typing.Any = None) -> dict:
        """
        Batch run in C++ with the GIL released (see quatnav::gpsins_batch). Returns a dict of arrays; each aid's report is a dict (innovation, nis, status, decision, inflation). With smooth, also 'smoothed': the Rauch-Tung-Striebel estimates (llh, v_n, q_nb, acc_bias, gyro_bias, sigma, baro_offset; acc_scale, gyro_scale with the scale-factor states) and the smoother's 'info' (nav/gps_ins/smoother.hpp).
        """
    def set_initial(self, q_nb: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[4, 1]"], v_n: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], v_valid: bool, acc_bias: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], gyro_bias: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"]) -> str:
        ...
    def set_params(self, params: GpsInsParams_f32) -> None:
        ...
    def set_state(self, state: dict) -> str:
        """
        Restore a state from get_state(); unknown and missing keys are refused.
        """
    def update_baro(self, h: typing.SupportsFloat | typing.SupportsIndex) -> tuple[GpsInsUpdate1_f32, GpsInsUpdate1_f32]:
        ...
    def update_compass(self, heading: typing.SupportsFloat | typing.SupportsIndex) -> GpsInsUpdate1_f32:
        ...
    def update_constraints(self) -> tuple[GpsInsUpdate3_f32, GpsInsUpdate3_f32, GpsInsUpdate2_f32]:
        ...
    def update_gps(self, lat: typing.SupportsFloat | typing.SupportsIndex, lon: typing.SupportsFloat | typing.SupportsIndex, h: typing.SupportsFloat | typing.SupportsIndex, v_n: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], pos_sigma: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], vel_sigma: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], age: typing.SupportsFloat | typing.SupportsIndex = 0.0, solution: typing.SupportsInt | typing.SupportsIndex = 0) -> tuple[GpsInsUpdate3_f32, GpsInsUpdate3_f32]:
        ...
    def update_gps_position(self, lat: typing.SupportsFloat | typing.SupportsIndex, lon: typing.SupportsFloat | typing.SupportsIndex, h: typing.SupportsFloat | typing.SupportsIndex, sigma: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], age: typing.SupportsFloat | typing.SupportsIndex = 0.0, solution: typing.SupportsInt | typing.SupportsIndex = 0) -> GpsInsUpdate3_f32:
        ...
    def update_gps_velocity(self, v_n: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], sigma: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"], age: typing.SupportsFloat | typing.SupportsIndex = 0.0) -> GpsInsUpdate3_f32:
        ...
    def update_mag(self, m: typing.Annotated[numpy.typing.ArrayLike, numpy.float32, "[3, 1]"]) -> GpsInsUpdate1_f32:
        ...
    def update_odometer(self, speed: typing.SupportsFloat | typing.SupportsIndex) -> GpsInsUpdate1_f32:
        ...
    @property
    def acc_bias(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float32], "[3, 1]"]:
        ...
    @property
    def acc_scale(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float32], "[3, 1]"]:
        ...
    @property
    def align_method(self) -> str:
        ...
    @property
    def at_rest(self) -> bool:
        ...
    @property
    def baro_offset(self) -> float:
        ...
    @property
    def counters(self) -> dict:
        ...
    @property
    def covariance(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float32], "[22, 22]"]:
        ...
    @property
    def gyro_bias(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float32], "[3, 1]"]:
        ...
    @property
    def gyro_scale(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float32], "[3, 1]"]:
        ...
    @property
    def heading_source(self) -> str:
        ...
    @property
    def llh(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[3, 1]"]:
        ...
    @property
    def n_states(self) -> int:
        ...
    @property
    def navigating(self) -> bool:
        ...
    @property
    def params(self) -> GpsInsParams_f32:
        ...
    @property
    def phase(self) -> int:
        ...
    @property
    def q_nb(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float32], "[4, 1]"]:
        ...
    @property
    def q_scale(self) -> float:
        ...
    @property
    def time(self) -> float:
        ...
    @property
    def v_n(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float32], "[3, 1]"]:
        ...
@typing.overload
def first_zero_norm_row(a: numpy.typing.NDArray[numpy.float32]) -> int:
    ...
@typing.overload
def first_zero_norm_row(a: typing.Annotated[numpy.typing.ArrayLike, numpy.float64]) -> int:
    """
    The first row of an (N, 3) array with norm <= sqrt(tiny) (non-finite rows left out), or -1.
    """
def flag_table() -> list:
    """
    The per-sample flags of every filter: a list of (name, bit mask, meaning).
    """
def gnss_solution_names() -> list:
    """
    Names of quatnav::GnssSolution by code (the receiver's solution kind of a GNSS fix).
    """
def gpsins_decision_names() -> list:
    """
    Names of quatnav::GpsInsDecision by code (what GpsInsFilter did with an aiding sample).
    """
def nav13_time_update_cost_ns(repeats: typing.SupportsInt | typing.SupportsIndex = 21, iterations: typing.SupportsInt | typing.SupportsIndex = 2000) -> dict:
    """
    Cost of one NavFilter13 time update per policy (ns, float64): the median over `repeats` of the mean over `iterations` consecutive predicts, the three policies interleaved in each repeat.
    """
def status_names() -> list:
    """
    The names of quatnav::Status by code.
    """
__version__: str = '0.1.0'
compiler: str = 'GCC 12.2.0'
