// Fields of the properties panel as data: {label, path, kind, value} and the limits of
// schemas/scene.schema.json ("> 0" sizes are exclusiveMin 0; intensities, offsets and sills are ≥ 0).

export const num = (label, path, value, limits = {}) => ({ label, path, kind: "number", value, ...limits });
export const positive = { exclusiveMin: 0, min: 0.01 };
export const nonNegative = { min: 0 };
