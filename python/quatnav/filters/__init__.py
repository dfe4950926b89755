"""The five filters: attitude (QuaternionEKF, EulerEKF, MargFilter) and navigation (NavFilter13, GpsInsFilter)."""
