// The hint shown after importing a Sweet Home 3D home without its furniture models (a bare Home.xml):
// the server draws each piece whose model it was not sent as a box and says so in a warning ("N
// furniture models were not found and M could not be read: those pieces are boxes (not found: …)",
// render/import/import_sh3d_models.cpp). Pure: file name and the import answer's warnings in, the
// hint's text (or null) out.
export function missingModelsHint(fileName, warnings) {
  const found = (warnings || []).map((w) => /^(\d+) furniture models were not found/.exec(String(w))).find(Boolean);
  const missing = found ? Number(found[1]) : 0;
  if (!missing) return null;
  const models = missing === 1 ? "1 furniture model" : `${missing} furniture models`;
  if (/\.(zip|sh3d)$/i.test(fileName || "")) {
    return `${models} named by the home ${missing === 1 ? "is" : "are"} not in ${fileName}, so the pieces using ` +
      `${missing === 1 ? "it" : "them"} are drawn as boxes (the warnings name ${missing === 1 ? "it" : "them"}). ` +
      "Zip the home with its whole furniture/ folder, or open the .sh3d file Sweet Home 3D saved.";
  }
  return `${fileName} came without its furniture models (${models} not found), so those pieces are drawn as ` +
    "boxes. To see the real furniture, open the .sh3d file Sweet Home 3D saved (it holds the models), or zip " +
    "Home.xml together with its furniture/ folder and open the zip.";
}
