"""File menu entries for real data: Import site (DEM + orthophoto), Import flight (a folder
of geotagged images, or an OpenDroneMap geo.txt / reference CSV) and Export flight plan
(QGroundControl, KML/KMZ, DJI WPML).

Each calls the same library code as its command (``designer new --site``, ``designer
import-flight``, ``designer export-flight``; docs/real-data.md), so a file made here is
the file the command makes. Errors are the commands' one-line messages, shown in the
Problems panel; nothing is written or changed when there is one.

* Import site asks for the DEM (checked at once: a file that cannot make a site is
  refused before anything else is asked), then the orthophoto (Cancel: none; checked
  with the DEM at once), then where to save the new project; the project is written
  and opened.
* Import flight replaces the open project's exposures by the flown photos (explicit
  exterior orientations, the camera the metadata names) as one undoable step; the 3D
  view draws their frusta and footprints like any other photos. Heights are the
  images' absolute heights (``designer import-flight --altitude relative`` offers the DJI
  relative altitude).
* Export flight plan writes the planned exposures in the format of the chosen file
  type, heights relative to the take-off point or above mean sea level as chosen.
"""

from __future__ import annotations

from pathlib import Path

from PySide6.QtWidgets import QFileDialog, QMenu

from designer.errors import DesignerError
from designer.gui.state.wording import count, error_text

#: Export flight plan: file type → (format, heights)
EXPORT_FILTERS = {
    "QGroundControl plan, heights relative to take-off (*.plan)": ("qgc", "relative"),
    "QGroundControl plan, heights above mean sea level (*.plan)": ("qgc", "amsl"),
    "DJI WPML mission, heights relative to take-off (*.kmz)": ("wpml", "relative"),
    "DJI WPML mission, heights above mean sea level (*.kmz)": ("wpml", "amsl"),
    "KML for Google Earth and GIS (*.kml *.kmz)": ("kml", "amsl"),
}
#: the suffix a file of each format gets when the typed name has none of its own
DEFAULT_SUFFIX = {"qgc": ".plan", "wpml": ".kmz", "kml": ".kml"}
GEOTIFF_FILTER = "GeoTIFF (*.tif *.tiff)"
FLIGHT_FILE_FILTER = "OpenDroneMap geo.txt or reference CSV (*.txt *.csv)"


class SiteFlightActions:
    """Import site, Import flight, Export flight plan for the window's document."""

    def __init__(self, window) -> None:
        self.window = window

    def build_menu(self, menu: QMenu) -> None:
        menu.addAction("Import &site (DEM + orthophoto)…", self.import_site)
        flight = menu.addMenu("Import &flight")
        flight.addAction("From a folder of &images…", self.import_flight_images)
        flight.addAction("From a &geo.txt or reference CSV…", self.import_flight_file)
        menu.addAction("&Export flight plan…", self.export_flight_plan)

    # ------------------------------------------------------------------ site
    def import_site(self) -> bool:
        w = self.window
        start = str(w.document.base_dir)
        dem, _ = QFileDialog.getOpenFileName(w, "Import site: the DEM", start, GEOTIFF_FILTER)
        if not dem:
            return False
        if not self.check_dem(Path(dem)):
            return False
        ortho, _ = QFileDialog.getOpenFileName(
            w, "Import site: the orthophoto (Cancel: none)", str(Path(dem).parent),
            GEOTIFF_FILTER)
        if ortho and not self.check_site(Path(dem), Path(ortho)):
            return False
        target, _ = QFileDialog.getSaveFileName(
            w, "Import site: save the new project as", str(Path(dem).with_suffix(".xml")),
            "designer project (*.xml)")
        if not target:
            return False
        if not target.lower().endswith(".xml"):
            target += ".xml"
        return self.make_site_project(Path(dem), Path(ortho) if ortho else None,
                                      Path(target))

    def check_dem(self, dem: Path) -> bool:
        """The chosen DEM can make a site on its own; else its error is shown at once
        (before the orthophoto is asked for) and False."""
        from designer.survey.site_project import check_site_dem

        try:
            check_site_dem(dem)
        except (DesignerError, OSError) as error:
            self.window.show_problems([error_text(error)], f"Cannot import the site {dem.name}")
            return False
        return True

    def check_site(self, dem: Path, orthophoto: Path) -> bool:
        """The DEM and the chosen orthophoto make a site together (readable, one
        coordinate system, overlapping); else the error is shown at once (before the
        save location is asked for) and False."""
        from designer.survey.site_project import site_project

        try:
            site_project(dem, orthophoto, dem.with_suffix(".xml"))
        except (DesignerError, OSError) as error:
            self.window.show_problems([error_text(error)],
                                      f"Cannot import the site {dem.name}")
            return False
        return True

    def make_site_project(self, dem: Path, orthophoto: Path | None, path: Path) -> bool:
        """Write the project of a site (as ``designer new PATH --site DEM --orthophoto
        ORTHO``) and open it; False with the error shown when it cannot be made."""
        from designer.project.new import write_new_project
        from designer.survey.site_project import site_project

        w = self.window
        if not w.file_actions.maybe_save():
            return False
        try:
            project = site_project(dem, orthophoto, path)
            write_new_project(path, project, {}, True, str(path), check_files=True)
        except (DesignerError, OSError) as error:
            w.show_problems([error_text(error)], f"Cannot import the site {dem.name}")
            return False
        return w.file_actions.open(path)

    # ------------------------------------------------------------------ flight in
    def import_flight_images(self) -> bool:
        folder = QFileDialog.getExistingDirectory(
            self.window, "Import flight: the folder of geotagged images",
            str(self.window.document.base_dir))
        return bool(folder) and self.import_flight(Path(folder))

    def import_flight_file(self) -> bool:
        path, _ = QFileDialog.getOpenFileName(
            self.window, "Import flight: geo.txt or reference CSV",
            str(self.window.document.base_dir), FLIGHT_FILE_FILTER)
        return bool(path) and self.import_flight(Path(path))

    def import_flight(self, source: Path) -> bool:
        """Replace the exposures by the flight in ``source`` (one undo step)."""
        from designer.flight.importer import replay_project

        w = self.window
        doc = w.document
        try:
            project = replay_project(source, doc.project, doc.base_dir)
        except (DesignerError, OSError) as error:
            w.show_problems([error_text(error)], f"Cannot import the flight {source.name}")
            return False
        photos = count(len(project.trajectory.exterior_orientations), "photo")
        w.editor.edit(project, f"Import flight ({photos})")
        w.show_problems([])
        w.statusBar().showMessage(f"imported {photos} from {source}", 8000)
        return True

    # ------------------------------------------------------------------ flight out
    def export_flight_plan(self) -> bool:
        w = self.window
        doc = w.document
        stem = doc.path.stem if doc.path is not None else "flight"
        start = str(doc.base_dir / f"{stem}.plan")
        path, chosen = QFileDialog.getSaveFileName(
            w, "Export flight plan", start, ";;".join(EXPORT_FILTERS))
        if not path:
            return False
        fmt, altitude = EXPORT_FILTERS.get(chosen, ("qgc", "relative"))
        path = Path(path)
        if fmt == "kml" and path.suffix.lower() not in (".kml", ".kmz"):
            path = path.with_name(path.name + DEFAULT_SUFFIX[fmt])
        elif fmt != "kml" and path.suffix.lower() != DEFAULT_SUFFIX[fmt]:
            path = path.with_name(path.name + DEFAULT_SUFFIX[fmt])
        return self.export_flight(path, fmt, altitude)

    def export_flight(self, path: Path, fmt: str, altitude: str) -> bool:
        """Write the planned flight as ``designer export-flight`` does."""
        from designer.flight.export import export_flight

        w = self.window
        try:
            spec = export_flight(w.document.project, w.document.base_dir, fmt, path,
                                 altitude=altitude)
        except (DesignerError, OSError) as error:
            w.show_problems([error_text(error)], "Flight plan not written")
            return False
        w.show_problems([])
        w.statusBar().showMessage(
            f"wrote {path}: {count(len(spec.exposures), 'photo')} ({fmt}, heights {altitude})",
            8000)
        return True
