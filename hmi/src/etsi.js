// CDD (ETSI TS 102 894-2) integer units → SI, and the names of the causes the HMI shows.

export const UNAVAILABLE = {
  latitude: 900000001,
  longitude: 1800000001,
  heading: 3601,
  speed: 16383,
};

export function latitudeDeg(v) {
  return v === undefined || v === UNAVAILABLE.latitude ? null : v / 1e7;
}
export function longitudeDeg(v) {
  return v === undefined || v === UNAVAILABLE.longitude ? null : v / 1e7;
}
export function headingDeg(v) {
  return v === undefined || v === UNAVAILABLE.heading ? null : v / 10;
}
export function speedMps(v) {
  return v === undefined || v === UNAVAILABLE.speed ? null : v / 100;
}
export function lengthM(v) {
  return v === undefined || v >= 1023 ? null : v / 10;
}
export function widthM(v) {
  return v === undefined || v >= 62 ? null : v / 10;
}

// CDD CauseCodeType, the causes a driver of the testbed meets; others show their numbers.
const CAUSES = {
  1: 'Traffic condition',
  2: 'Accident',
  3: 'Roadworks',
  91: 'Vehicle breakdown',
  92: 'Post-crash',
  94: 'Stationary vehicle',
  95: 'Emergency vehicle approaching',
  97: 'Collision risk',
  99: 'Dangerous situation',
};
const COLLISION_RISK_SUB = {
  1: 'longitudinal',
  2: 'crossing',
  3: 'lateral',
  4: 'vulnerable road user',
};

export function causeText(cause, subcause) {
  const name = CAUSES[cause] ?? `Cause ${cause}`;
  if (cause === 97 && COLLISION_RISK_SUB[subcause]) {
    return `${name} (${COLLISION_RISK_SUB[subcause]})`;
  }
  return subcause ? `${name} (${subcause})` : name;
}

const EARTH_RADIUS_M = 6371008.8;

// East/north offset in metres of (lat, lon) from (lat0, lon0); equirectangular, which is far
// inside a pixel at the map's few hundred metres.
export function offsetM(lat0, lon0, lat, lon) {
  const rad = Math.PI / 180;
  return {
    east: (lon - lon0) * rad * Math.cos(lat0 * rad) * EARTH_RADIUS_M,
    north: (lat - lat0) * rad * EARTH_RADIUS_M,
  };
}

export function fixText(fix) {
  return { none: 'No fix', '2d': '2D fix', '3d': '3D fix' }[fix] ?? 'Unknown';
}
