<?xml version="1.0" encoding="utf-8"?>
<!DOCTYPE TS>
<TS version="2.1" language="de_DE">
<context>
    <name>relume::ClickPhotoView</name>
    <message>
        <source>No photo</source>
        <translation>Kein Foto</translation>
    </message>
</context>
<context>
    <name>relume::ClicksPanel</name>
    <message>
        <source>Workspace</source>
        <translation>Arbeitsbereich</translation>
    </message>
    <message>
        <source>A reconstruction workspace or COLMAP model folder (cameras), or a new folder: the clicks are kept there as clicks.json</source>
        <translation>Ein Rekonstruktions-Arbeitsbereich oder COLMAP-Modellordner (Kameras) oder ein neuer Ordner: die Klicks werden dort als clicks.json gespeichert</translation>
    </message>
    <message>
        <source>Choose...</source>
        <translation>Wählen...</translation>
    </message>
    <message>
        <source>Photos</source>
        <translation>Fotos</translation>
    </message>
    <message>
        <source>from the workspace</source>
        <translation>aus dem Arbeitsbereich</translation>
    </message>
    <message>
        <source>Open</source>
        <translation>Öffnen</translation>
    </message>
    <message>
        <source>Choose the workspace</source>
        <translation>Arbeitsbereich wählen</translation>
    </message>
    <message>
        <source>The photo to click corners in</source>
        <translation>Das Foto, in dem Ecken geklickt werden</translation>
    </message>
    <message>
        <source>A second photo: proposals for the corner appear here</source>
        <translation>Ein zweites Foto: hier erscheinen Vorschläge für die Ecke</translation>
    </message>
    <message>
        <source>Fit</source>
        <translation>Einpassen</translation>
    </message>
    <message>
        <source>1:1</source>
        <translation>1:1</translation>
    </message>
    <message>
        <source>The whole photo (F)</source>
        <translation>Das ganze Foto (F)</translation>
    </message>
    <message>
        <source>One photo pixel per screen pixel</source>
        <translation>Ein Fotopixel pro Bildschirmpixel</translation>
    </message>
    <message>
        <source>Point</source>
        <translation>Punkt</translation>
    </message>
    <message>
        <source>Clicked in</source>
        <translation>Geklickt in</translation>
    </message>
    <message>
        <source>Error</source>
        <translation>Fehler</translation>
    </message>
    <message>
        <source>Depth</source>
        <translation>Tiefe</translation>
    </message>
    <message>
        <source>New point</source>
        <translation>Neuer Punkt</translation>
    </message>
    <message>
        <source>The next click starts a new point (N)</source>
        <translation>Der nächste Klick beginnt einen neuen Punkt (N)</translation>
    </message>
    <message>
        <source>Delete</source>
        <translation>Löschen</translation>
    </message>
    <message>
        <source>Deletes the selected points (and the polygons left with fewer than 3 corners)</source>
        <translation>Löscht die gewählten Punkte (und Polygone mit danach weniger als 3 Ecken)</translation>
    </message>
    <message>
        <source>Merge</source>
        <translation>Zusammenführen</translation>
    </message>
    <message>
        <source>The second picked point&apos;s clicks go to the first; polygons follow</source>
        <translation>Die Klicks des zweiten gewählten Punkts gehen an den ersten; Polygone folgen</translation>
    </message>
    <message>
        <source>Pick two points to merge (Ctrl+click).</source>
        <translation>Zwei Punkte zum Zusammenführen wählen (Strg+Klick).</translation>
    </message>
    <message>
        <source> m</source>
        <translation> m</translation>
    </message>
    <message>
        <source>Measured</source>
        <translation>Gemessen</translation>
    </message>
    <message>
        <source>The current point&apos;s measured position (a control point when it is clicked too); with no point current, a new point only measured (a corner no photo shows)</source>
        <translation>Die gemessene Position des aktuellen Punkts (ein Passpunkt, wenn er auch geklickt ist); ohne aktuellen Punkt ein neuer, nur gemessener Punkt (eine Ecke, die kein Foto zeigt)</translation>
    </message>
    <message>
        <source>Clear</source>
        <translation>Leeren</translation>
    </message>
    <message>
        <source>Forget the current point&apos;s measured position</source>
        <translation>Die gemessene Position des aktuellen Punkts vergessen</translation>
    </message>
    <message>
        <source>Polygon</source>
        <translation>Polygon</translation>
    </message>
    <message>
        <source>Corners</source>
        <translation>Ecken</translation>
    </message>
    <message>
        <source>Group</source>
        <translation>Gruppe</translation>
    </message>
    <message>
        <source>Lamp</source>
        <translation>Lampe</translation>
    </message>
    <message>
        <source>Rectangle</source>
        <translation>Rechteck</translation>
    </message>
    <message>
        <source>Plane</source>
        <translation>Ebene</translation>
    </message>
    <message>
        <source>Double-click a name, group, lamp name or plane key to change it. Tick Lamp for a lamp (its name: the text, else the polygon&apos;s); polygons with the same plane key share one plane</source>
        <translation>Doppelklick auf Name, Gruppe, Lampenname oder Ebenenschlüssel ändert ihn. Lampe ankreuzen für eine Lampe (ihr Name: der Text, sonst der des Polygons); Polygone mit gleichem Ebenenschlüssel teilen eine Ebene</translation>
    </message>
    <message>
        <source>name (optional)</source>
        <translation>Name (optional)</translation>
    </message>
    <message>
        <source>The new polygon&apos;s name</source>
        <translation>Der Name des neuen Polygons</translation>
    </message>
    <message>
        <source>Polygon from picked</source>
        <translation>Polygon aus gewählten</translation>
    </message>
    <message>
        <source>A polygon through the picked points, in the order picked (P)</source>
        <translation>Ein Polygon durch die gewählten Punkte, in der gewählten Reihenfolge (P)</translation>
    </message>
    <message>
        <source>Delete polygon</source>
        <translation>Polygon löschen</translation>
    </message>
    <message>
        <source>Undo</source>
        <translation>Rückgängig</translation>
    </message>
    <message>
        <source>Redo</source>
        <translation>Wiederholen</translation>
    </message>
    <message>
        <source>Project</source>
        <translation>Projekt</translation>
    </message>
    <message>
        <source>The Relume project the model is written to</source>
        <translation>Das Relume-Projekt, in das das Modell geschrieben wird</translation>
    </message>
    <message>
        <source>Focal length</source>
        <translation>Brennweite</translation>
    </message>
    <message>
        <source> px</source>
        <translation> px</translation>
    </message>
    <message>
        <source>from EXIF / calibration</source>
        <translation>aus EXIF / Kalibrierung</translation>
    </message>
    <message>
        <source>Without a reconstruction: the camera&apos;s focal length in pixels (the Photos panel&apos;s calibration is used when there is one)</source>
        <translation>Ohne Rekonstruktion: die Brennweite der Kamera in Pixeln (die Kalibrierung des Fotos-Panels wird verwendet, wenn vorhanden)</translation>
    </message>
    <message>
        <source>Build model</source>
        <translation>Modell bauen</translation>
    </message>
    <message>
        <source>Triangulate the points, fit the polygons, write the project and preprocess it</source>
        <translation>Punkte triangulieren, Polygone anpassen, Projekt schreiben und vorverarbeiten</translation>
    </message>
    <message>
        <source>Open a workspace to click corners in its photos.</source>
        <translation>Einen Arbeitsbereich öffnen, um Ecken in seinen Fotos zu klicken.</translation>
    </message>
    <message>
        <source>Choose a workspace folder first.</source>
        <translation>Zuerst einen Arbeitsbereich-Ordner wählen.</translation>
    </message>
    <message>
        <source>Cannot create the folder %1.</source>
        <translation>Der Ordner %1 kann nicht angelegt werden.</translation>
    </message>
    <message>
        <source>%1 photos from %2</source>
        <translation>%1 Fotos aus %2</translation>
    </message>
    <message>
        <source>New point %1</source>
        <translation>Neuer Punkt %1</translation>
    </message>
    <message>
        <source>Click %1 in %2</source>
        <translation>%1 in %2 klicken</translation>
    </message>
    <message>
        <source>Accept the match of %1 in %2</source>
        <translation>Zuordnung von %1 in %2 annehmen</translation>
    </message>
    <message>
        <source>Move %1 in %2</source>
        <translation>%1 in %2 verschieben</translation>
    </message>
    <message>
        <source>Delete point %1</source>
        <translation>Punkt %1 löschen</translation>
    </message>
    <message>
        <source>Delete %1 points</source>
        <translation>%1 Punkte löschen</translation>
    </message>
    <message>
        <source>Merge %1 into %2</source>
        <translation>%1 mit %2 zusammenführen</translation>
    </message>
    <message>
        <source>Measure %1</source>
        <translation>%1 messen</translation>
    </message>
    <message>
        <source>Forget the measure of %1</source>
        <translation>Messung von %1 vergessen</translation>
    </message>
    <message>
        <source>New measured point %1</source>
        <translation>Neuer gemessener Punkt %1</translation>
    </message>
    <message>
        <source>Pick three or more corners in order first (Ctrl+click them, or select them in the list).</source>
        <translation>Zuerst drei oder mehr Ecken der Reihe nach wählen (Strg+Klick oder in der Liste auswählen).</translation>
    </message>
    <message>
        <source>There is a polygon called %1 already.</source>
        <translation>Es gibt schon ein Polygon namens %1.</translation>
    </message>
    <message>
        <source>New polygon %1</source>
        <translation>Neues Polygon %1</translation>
    </message>
    <message>
        <source>Delete polygon %1</source>
        <translation>Polygon %1 löschen</translation>
    </message>
    <message>
        <source>%1 is a lamp</source>
        <translation>%1 ist eine Lampe</translation>
    </message>
    <message>
        <source>%1 is not a lamp</source>
        <translation>%1 ist keine Lampe</translation>
    </message>
    <message>
        <source>A polygon needs a name of its own.</source>
        <translation>Ein Polygon braucht einen eigenen Namen.</translation>
    </message>
    <message>
        <source>Rename %1 to %2</source>
        <translation>%1 in %2 umbenennen</translation>
    </message>
    <message>
        <source>%1 in group %2</source>
        <translation>%1 in Gruppe %2</translation>
    </message>
    <message>
        <source>%1 is a rectangle</source>
        <translation>%1 ist ein Rechteck</translation>
    </message>
    <message>
        <source>%1 is not a rectangle</source>
        <translation>%1 ist kein Rechteck</translation>
    </message>
    <message>
        <source>%1 shares plane %2</source>
        <translation>%1 teilt Ebene %2</translation>
    </message>
    <message>
        <source>clicked in one photo: click it in another</source>
        <translation>in einem Foto geklickt: in einem weiteren klicken</translation>
    </message>
    <message>
        <source>no cameras yet</source>
        <translation>noch keine Kameras</translation>
    </message>
    <message>
        <source>measured (%1, %2, %3)</source>
        <translation>gemessen (%1, %2, %3)</translation>
    </message>
    <message>
        <source>%1 px</source>
        <translation>%1 px</translation>
    </message>
    <message>
        <source>weak (%1°)</source>
        <translation>schwach (%1°)</translation>
    </message>
    <message>
        <source>good (%1°)</source>
        <translation>gut (%1°)</translation>
    </message>
    <message>
        <source>Clicked in photos taken from nearly the same direction: click it in a photo further to the side</source>
        <translation>In Fotos aus fast derselben Richtung geklickt: in einem Foto weiter seitlich klicken</translation>
    </message>
    <message>
        <source>measured</source>
        <translation>gemessen</translation>
    </message>
    <message>
        <source>%1 points, %2 polygons; %3. Saved in %4</source>
        <translation>%1 Punkte, %2 Polygone; %3. Gespeichert in %4</translation>
    </message>
    <message>
        <source>cameras from the reconstruction</source>
        <translation>Kameras aus der Rekonstruktion</translation>
    </message>
    <message>
        <source>no cameras yet (solved from the clicks when building)</source>
        <translation>noch keine Kameras (beim Bauen aus den Klicks bestimmt)</translation>
    </message>
    <message>
        <source>Open a workspace: its photos appear here side by side.</source>
        <translation>Einen Arbeitsbereich öffnen: seine Fotos erscheinen hier nebeneinander.</translation>
    </message>
    <message>
        <source>Click a corner in either photo to start a point. Ctrl+click points to pick polygon corners in order.</source>
        <translation>Eine Ecke in einem der Fotos klicken, um einen Punkt zu beginnen. Strg+Klick auf Punkte wählt Polygonecken der Reihe nach.</translation>
    </message>
    <message>
        <source>Point %1: click it in the other photo; drag a cross to move it. N starts a new point.</source>
        <translation>Punkt %1: im anderen Foto klicken; ein Kreuz ziehen, um es zu verschieben. N beginnt einen neuen Punkt.</translation>
    </message>
    <message>
        <source>Open a workspace and click the corners first.</source>
        <translation>Zuerst einen Arbeitsbereich öffnen und die Ecken klicken.</translation>
    </message>
    <message>
        <source>Choose where the project goes first.</source>
        <translation>Zuerst wählen, wohin das Projekt kommt.</translation>
    </message>
    <message>
        <source>Building the model from the clicks</source>
        <translation>Modell aus den Klicks bauen</translation>
    </message>
    <message>
        <source>Warning: %1</source>
        <translation>Warnung: %1</translation>
    </message>
    <message>
        <source>%1 points (largest reprojection error %2 px), %3 polygons, %4 lamps: %5</source>
        <translation>%1 Punkte (größter Rückprojektionsfehler %2 px), %3 Polygone, %4 Lampen: %5</translation>
    </message>
    <message>
        <source>Scale</source>
        <translation>Maßstab</translation>
    </message>
    <message>
        <source>point</source>
        <translation>Punkt</translation>
    </message>
    <message>
        <source>floor points</source>
        <translation>Bodenpunkte</translation>
    </message>
    <message>
        <source>Without a reconstruction and without three measured clicked points: two points, their distance, and three or more floor points (names, comma-separated) set the metric frame</source>
        <translation>Ohne Rekonstruktion und ohne drei gemessene geklickte Punkte: zwei Punkte, ihr Abstand und drei oder mehr Bodenpunkte (Namen, durch Kommas getrennt) legen das metrische System fest</translation>
    </message>
    <message>
        <source>Point %1: click a ring to accept that proposal (Enter: the best; 1-3), or click the corner where it is (Shift+click: exactly there, even on a ring). N starts a new point.</source>
        <translation>Punkt %1: einen Ring klicken, um diesen Vorschlag anzunehmen (Enter: den besten; 1-3), oder die Ecke dort klicken, wo sie ist (Umschalt+Klick: genau dort, auch auf einem Ring). N beginnt einen neuen Punkt.</translation>
    </message>
    <message>
        <source>Points and polygons</source>
        <translation>Punkte und Polygone</translation>
    </message>
    <message>
        <source>The points and polygons in 3-D with the cameras (drag to orbit, wheel to zoom)</source>
        <translation>Die Punkte und Polygone in 3-D mit den Kameras (Ziehen zum Drehen, Mausrad zum Zoomen)</translation>
    </message>
    <message>
        <source>3-D</source>
        <translation>3-D</translation>
    </message>
</context>
<context>
    <name>relume::Document</name>
    <message>
        <source>lamp %1</source>
        <translation>Lampe %1</translation>
    </message>
    <message>
        <source>add %1</source>
        <translation>%1 hinzufügen</translation>
    </message>
    <message>
        <source>remove %1</source>
        <translation>%1 entfernen</translation>
    </message>
    <message>
        <source>move %1</source>
        <translation>%1 verschieben</translation>
    </message>
    <message>
        <source>change %1</source>
        <translation>%1 ändern</translation>
    </message>
    <message>
        <source>reference patch of %1</source>
        <translation>Referenzfeld von %1</translation>
    </message>
    <message>
        <source>automatic reference of %1</source>
        <translation>automatische Referenz von %1</translation>
    </message>
    <message>
        <source>reference region on %1</source>
        <translation>Referenzbereich auf %1</translation>
    </message>
    <message>
        <source>no reference regions on %1</source>
        <translation>keine Referenzbereiche auf %1</translation>
    </message>
</context>
<context>
    <name>relume::EditTool</name>
    <message>
        <source>Click a surface to put a virtual lamp 2 cm in front of it.</source>
        <translation>Klicken Sie auf eine Fläche, um eine virtuelle Leuchte 2 cm davor anzubringen.</translation>
    </message>
    <message>
        <source>Click a floor or a table top to stand the box on it.</source>
        <translation>Klicken Sie auf einen Boden oder eine Tischplatte, um die Kiste daraufzustellen.</translation>
    </message>
    <message>
        <source>No surface there: click on the room.</source>
        <translation>Dort ist keine Fläche: Klicken Sie in den Raum.</translation>
    </message>
    <message>
        <source>Lamp</source>
        <translation>Leuchte</translation>
    </message>
    <message>
        <source>Added %1 (%2 ms).</source>
        <translation>%1 hinzugefügt (%2 ms).</translation>
    </message>
    <message>
        <source>Objects stand on floors and tables: click a horizontal surface.</source>
        <translation>Objekte stehen auf Böden und Tischen: Klicken Sie auf eine waagerechte Fläche.</translation>
    </message>
    <message>
        <source>Box</source>
        <translation>Kiste</translation>
    </message>
    <message>
        <source>Not moved: %1</source>
        <translation>Nicht verschoben: %1</translation>
    </message>
    <message>
        <source>Click a texel of %1 whose colour its shadowed parts should take.</source>
        <translation>Klicken Sie auf ein Texel von %1, dessen Farbe die verschatteten Teile annehmen sollen.</translation>
    </message>
    <message>
        <source>That is not %1: click on it, or press Esc.</source>
        <translation>Das ist nicht %1: Klicken Sie darauf oder drücken Sie Esc.</translation>
    </message>
    <message>
        <source>Reference patch of %1 set: recompute to see it.</source>
        <translation>Referenzfeld von %1 gesetzt: neu berechnen, um es zu sehen.</translation>
    </message>
    <message>
        <source>Click a floor or a table top to stand %1 on it.</source>
        <translation>Klicken Sie auf einen Boden oder eine Tischplatte, um %1 daraufzustellen.</translation>
    </message>
    <message>
        <source>%1 cannot stand there: %2</source>
        <translation>%1 kann dort nicht stehen: %2</translation>
    </message>
    <message>
        <source>Paint over the shadowed part of %1 (drag); then click the texel it should take its colour from.</source>
        <translation>Übermalen Sie den verschatteten Teil von %1 (ziehen); klicken Sie dann das Texel, dessen Farbe er übernehmen soll.</translation>
    </message>
    <message>
        <source>Reference region painted on %1: recompute to see it.</source>
        <translation>Referenzbereich auf %1 gemalt: neu berechnen, um ihn zu sehen.</translation>
    </message>
    <message>
        <source>Now click the texel of %1 whose colour the painted shadow should take.</source>
        <translation>Klicken Sie jetzt das Texel von %1, dessen Farbe der gemalte Schatten übernehmen soll.</translation>
    </message>
    <message>
        <source>Added %1.</source>
        <translation>%1 hinzugefügt.</translation>
    </message>
</context>
<context>
    <name>relume::InspectorPanel</name>
    <message>
        <source>Radiosity B</source>
        <translation>Radiosität B</translation>
    </message>
    <message>
        <source>Irradiance E</source>
        <translation>Bestrahlungsstärke E</translation>
    </message>
    <message>
        <source>Display factor D</source>
        <translation>Anzeigefaktor D</translation>
    </message>
    <message>
        <source>Ratio B / D</source>
        <translation>Verhältnis B / D</translation>
    </message>
    <message>
        <source>Reflectance</source>
        <translation>Reflexionsgrad</translation>
    </message>
    <message>
        <source>Shadow-free texture T_final</source>
        <translation>Schattenfreie Textur T_final</translation>
    </message>
    <message>
        <source>Element level</source>
        <translation>Elementebene</translation>
    </message>
    <message>
        <source>Visibility from a lamp</source>
        <translation>Sichtbarkeit von einer Lampe</translation>
    </message>
    <message>
        <source>What colours the elements (RGB quantities: the mean of R, G and B)</source>
        <translation>Was die Elemente färbt (RGB-Größen: der Mittelwert von R, G und B)</translation>
    </message>
    <message>
        <source>The lamp whose links are classed: visible, partly hidden, or hidden</source>
        <translation>Die Lampe, deren Verbindungen eingeteilt werden: sichtbar, teilweise verdeckt oder verdeckt</translation>
    </message>
    <message>
        <source>Show the elements of one polygon only</source>
        <translation>Nur die Elemente eines Polygons zeigen</translation>
    </message>
    <message>
        <source>Viewport&apos;s mesh</source>
        <translation>Netz der Ansicht</translation>
    </message>
    <message>
        <source>Other mesh</source>
        <translation>Anderes Netz</translation>
    </message>
    <message>
        <source>The refined and the interactive mesh: the other one is a second session, built as a job</source>
        <translation>Das verfeinerte und das interaktive Netz: das andere ist eine zweite Sitzung, als Auftrag erstellt</translation>
    </message>
    <message>
        <source>Colour by</source>
        <translation>Färben nach</translation>
    </message>
    <message>
        <source>Polygon</source>
        <translation>Polygon</translation>
    </message>
    <message>
        <source>Role</source>
        <translation>Rolle</translation>
    </message>
    <message>
        <source>Source</source>
        <translation>Quelle</translation>
    </message>
    <message>
        <source>Receiver</source>
        <translation>Empfänger</translation>
    </message>
    <message>
        <source>F</source>
        <translation>F</translation>
    </message>
    <message>
        <source>V</source>
        <translation>V</translation>
    </message>
    <message>
        <source>F × V</source>
        <translation>F × V</translation>
    </message>
    <message>
        <source>Type</source>
        <translation>Typ</translation>
    </message>
    <message>
        <source>Oracle error</source>
        <translation>Fehler des Orakels</translation>
    </message>
    <message>
        <source>The links the picked element holds: those it gathers by, and those it sends by</source>
        <translation>Die Verbindungen des gewählten Elements: über die es empfängt und über die es sendet</translation>
    </message>
    <message>
        <source>Links of the picked element</source>
        <translation>Verbindungen des gewählten Elements</translation>
    </message>
    <message>
        <source>Counts per polygon</source>
        <translation>Anzahlen je Polygon</translation>
    </message>
    <message>
        <source>All polygons</source>
        <translation>Alle Polygone</translation>
    </message>
    <message>
        <source>No room open.</source>
        <translation>Kein Raum geöffnet.</translation>
    </message>
    <message>
        <source>Light from %1</source>
        <translation>Licht von %1</translation>
    </message>
    <message>
        <source>VISIBLE</source>
        <translation>SICHTBAR</translation>
    </message>
    <message>
        <source>INVISIBLE</source>
        <translation>VERDECKT</translation>
    </message>
    <message>
        <source>PARTIAL</source>
        <translation>TEILWEISE</translation>
    </message>
    <message>
        <source>%1: %2 elements shown of %3 leaves; %4 links in the engine</source>
        <translation>%1: %2 Elemente gezeigt von %3 Blättern; %4 Verbindungen in der Engine</translation>
    </message>
    <message>
        <source>interactive mesh</source>
        <translation>interaktives Netz</translation>
    </message>
    <message>
        <source>refined mesh</source>
        <translation>verfeinertes Netz</translation>
    </message>
    <message>
        <source>cluster %1</source>
        <translation>Cluster %1</translation>
    </message>
    <message>
        <source>%1 #%2 (level %3)</source>
        <translation>%1 Nr. %2 (Ebene %3)</translation>
    </message>
    <message>
        <source>visible</source>
        <translation>sichtbar</translation>
    </message>
    <message>
        <source>invisible</source>
        <translation>verdeckt</translation>
    </message>
    <message>
        <source>partial</source>
        <translation>teilweise</translation>
    </message>
    <message>
        <source>gathers</source>
        <translation>empfängt</translation>
    </message>
    <message>
        <source>sends</source>
        <translation>sendet</translation>
    </message>
    <message>
        <source>Elements, leaves and links per polygon (the 6 with the most links)</source>
        <translation>Elemente, Blätter und Verbindungen je Polygon (die 6 mit den meisten Verbindungen)</translation>
    </message>
    <message>
        <source>elements</source>
        <translation>Elemente</translation>
    </message>
    <message>
        <source>leaves</source>
        <translation>Blätter</translation>
    </message>
    <message>
        <source>links received</source>
        <translation>empfangene Verbindungen</translation>
    </message>
    <message>
        <source>Building the other mesh for the inspector</source>
        <translation>Das andere Netz für den Inspektor wird erstellt</translation>
    </message>
</context>
<context>
    <name>relume::JobRunner</name>
    <message>
        <source>Cancelled; nothing was changed.</source>
        <translation>Abgebrochen; nichts wurde geändert.</translation>
    </message>
</context>
<context>
    <name>relume::LightsPanel</name>
    <message>
        <source>No room open.</source>
        <translation>Kein Raum geöffnet.</translation>
    </message>
    <message>
        <source>Lamp strengths estimated by the preprocess (%1). Drag a slider to dim or boost a lamp; untick to switch it off.</source>
        <translation>Lampenstärken aus der Vorverarbeitung geschätzt (%1). Ziehen Sie einen Regler, um eine Lampe zu dimmen oder zu verstärken; Häkchen entfernen schaltet sie aus.</translation>
    </message>
    <message>
        <source>Lamp %1</source>
        <translation>Lampe %1</translation>
    </message>
    <message>
        <source>On</source>
        <translation>An</translation>
    </message>
    <message>
        <source>Intensity, 0-400 % of the photographed lamp</source>
        <translation>Intensität, 0–400 % der fotografierten Lampe</translation>
    </message>
    <message>
        <source>Colour of the lamp</source>
        <translation>Farbe der Lampe</translation>
    </message>
    <message>
        <source>its photometric file&apos;s flux</source>
        <translation>Lichtstrom ihrer photometrischen Datei</translation>
    </message>
    <message>
        <source>Emits as %1 says (%2, %3 lm)</source>
        <translation>Strahlt ab, wie %1 angibt (%2, %3 lm)</translation>
    </message>
    <message>
        <source>measured in the HDR photo</source>
        <translation>im HDR-Foto gemessen</translation>
    </message>
    <message>
        <source>least-squares fit</source>
        <translation>Ausgleichsrechnung (kleinste Quadrate)</translation>
    </message>
    <message>
        <source>Eq. 2, all lamps equal</source>
        <translation>Gl. 2, alle Lampen gleich</translation>
    </message>
    <message>
        <source>Estimate: %1, %2, %3 W/m² (%4)</source>
        <translation>Schätzung: %1, %2, %3 W/m² (%4)</translation>
    </message>
    <message>
        <source>Virtual lamps</source>
        <translation>Virtuelle Leuchten</translation>
    </message>
    <message>
        <source>Add a lamp (click a surface)</source>
        <translation>Leuchte hinzufügen (auf eine Fläche klicken)</translation>
    </message>
    <message>
        <source>Then click a surface in the viewport: a 30 cm lamp appears 2 cm in front of it, facing away from it. Drag it to move it along that surface.</source>
        <translation>Klicken Sie dann in der Ansicht auf eine Fläche: Eine 30-cm-Leuchte erscheint 2 cm davor, von ihr abgewandt. Ziehen Sie sie, um sie entlang dieser Fläche zu verschieben.</translation>
    </message>
    <message>
        <source>Power, 0-400 % of the brightest real lamp</source>
        <translation>Leistung, 0–400 % der hellsten realen Leuchte</translation>
    </message>
    <message>
        <source> m</source>
        <translation> m</translation>
    </message>
    <message>
        <source>Width of the square lamp</source>
        <translation>Breite der quadratischen Leuchte</translation>
    </message>
    <message>
        <source>drop </source>
        <translation>Abhängung </translation>
    </message>
    <message>
        <source>Distance from the surface it was put on (a pendant&apos;s suspension)</source>
        <translation>Abstand von der Fläche, an der sie angebracht wurde (Abhängung einer Pendelleuchte)</translation>
    </message>
    <message>
        <source>Delete</source>
        <translation>Löschen</translation>
    </message>
    <message>
        <source>Not moved: %1</source>
        <translation>Nicht verschoben: %1</translation>
    </message>
</context>
<context>
    <name>relume::MainWindow</name>
    <message>
        <source>Lights</source>
        <translation>Beleuchtung</translation>
    </message>
    <message>
        <source>Cancel</source>
        <translation>Abbrechen</translation>
    </message>
    <message>
        <source>Relume</source>
        <translation>Relume</translation>
    </message>
    <message>
        <source>&amp;File</source>
        <translation>&amp;Datei</translation>
    </message>
    <message>
        <source>&amp;Open...</source>
        <translation>Ö&amp;ffnen...</translation>
    </message>
    <message>
        <source>Open a room or a Relume project</source>
        <translation>Einen Raum oder ein Relume-Projekt öffnen</translation>
    </message>
    <message>
        <source>Open &amp;OBJ + JSON...</source>
        <translation>&amp;OBJ + JSON öffnen...</translation>
    </message>
    <message>
        <source>Open a room</source>
        <translation>Einen Raum öffnen</translation>
    </message>
    <message>
        <source>Room geometry (*.obj)</source>
        <translation>Raumgeometrie (*.obj)</translation>
    </message>
    <message>
        <source>Open &amp;Recent</source>
        <translation>&amp;Zuletzt geöffnet</translation>
    </message>
    <message>
        <source>&amp;Save</source>
        <translation>&amp;Speichern</translation>
    </message>
    <message>
        <source>Save the project as</source>
        <translation>Projekt speichern unter</translation>
    </message>
    <message>
        <source>Save &amp;As...</source>
        <translation>Speichern &amp;unter...</translation>
    </message>
    <message>
        <source>&amp;Quit</source>
        <translation>&amp;Beenden</translation>
    </message>
    <message>
        <source>&amp;Edit</source>
        <translation>&amp;Bearbeiten</translation>
    </message>
    <message>
        <source>&amp;Undo</source>
        <translation>&amp;Rückgängig</translation>
    </message>
    <message>
        <source>&amp;Redo</source>
        <translation>&amp;Wiederholen</translation>
    </message>
    <message>
        <source>&amp;View</source>
        <translation>&amp;Ansicht</translation>
    </message>
    <message>
        <source>&amp;Relit (texture × B / D)</source>
        <translation>&amp;Neu beleuchtet (Textur × B / D)</translation>
    </message>
    <message>
        <source>Relit, r&amp;atio only (texture × B / B_orig)</source>
        <translation>Neu beleuchtet, nur &amp;Verhältnis (Textur × B / B_orig)</translation>
    </message>
    <message>
        <source>Original &amp;photo</source>
        <translation>&amp;Originalfoto</translation>
    </message>
    <message>
        <source>&amp;Unoccluded textures (shadows removed)</source>
        <translation>Texturen &amp;ohne Schatten (Schatten entfernt)</translation>
    </message>
    <message>
        <source>Radiosity &amp;B</source>
        <translation>Radiosität &amp;B</translation>
    </message>
    <message>
        <source>Display factor &amp;D</source>
        <translation>Anzeigefaktor &amp;D</translation>
    </message>
    <message>
        <source>&amp;Leaf outlines</source>
        <translation>&amp;Elementgrenzen</translation>
    </message>
    <message>
        <source>&amp;False colour luminance</source>
        <translation>Leuchtdichte in &amp;Falschfarben</translation>
    </message>
    <message>
        <source>Exposure +½ EV</source>
        <translation>Belichtung +½ LW</translation>
    </message>
    <message>
        <source>Exposure −½ EV</source>
        <translation>Belichtung −½ LW</translation>
    </message>
    <message>
        <source>Exposure of the &amp;photo</source>
        <translation>Belichtung des &amp;Fotos</translation>
    </message>
    <message>
        <source>&amp;Through the photo&apos;s camera</source>
        <translation>&amp;Durch die Kamera des Fotos</translation>
    </message>
    <message>
        <source>Free &amp;orbit</source>
        <translation>Freie &amp;Umlaufansicht</translation>
    </message>
    <message>
        <source>&amp;Lighting</source>
        <translation>&amp;Licht</translation>
    </message>
    <message>
        <source>&amp;All lamps as photographed</source>
        <translation>&amp;Alle Lampen wie fotografiert</translation>
    </message>
    <message>
        <source>all lamps as photographed</source>
        <translation>alle Lampen wie fotografiert</translation>
    </message>
    <message>
        <source>All lamps &amp;off</source>
        <translation>Alle Lampen a&amp;us</translation>
    </message>
    <message>
        <source>all lamps off</source>
        <translation>alle Lampen aus</translation>
    </message>
    <message>
        <source>&amp;Help</source>
        <translation>&amp;Hilfe</translation>
    </message>
    <message>
        <source>&amp;About Relume</source>
        <translation>&amp;Über Relume</translation>
    </message>
    <message>
        <source>About Relume</source>
        <translation>Über Relume</translation>
    </message>
    <message>
        <source>&lt;b&gt;Relume&lt;/b&gt; relights photographed rooms: switch real lamps off, dim or tint them, add virtual lamps and objects, and see the photograph respond.&lt;br&gt;&lt;br&gt;Method: Loscos, Drettakis, Robert 2000, &lt;i&gt;Interactive virtual relighting of real scenes&lt;/i&gt; — hierarchical radiosity with clustering, real shadows removed from the photo textures, display of texture × B / D.</source>
        <translation>&lt;b&gt;Relume&lt;/b&gt; beleuchtet fotografierte Räume neu: echte Lampen ausschalten, dimmen oder einfärben, virtuelle Lampen und Objekte hinzufügen und sehen, wie das Foto reagiert.&lt;br&gt;&lt;br&gt;Verfahren: Loscos, Drettakis, Robert 2000, &lt;i&gt;Interactive virtual relighting of real scenes&lt;/i&gt; — hierarchische Radiosität mit Clustering, echte Schatten aus den Fototexturen entfernt, Anzeige von Textur × B / D.</translation>
    </message>
    <message>
        <source>Another job is running; wait for it or cancel it first.</source>
        <translation>Eine andere Aufgabe läuft; warten Sie oder brechen Sie sie zuerst ab.</translation>
    </message>
    <message>
        <source>Opening %1</source>
        <translation>Öffne %1</translation>
    </message>
    <message>
        <source>Opened %1</source>
        <translation>%1 geöffnet</translation>
    </message>
    <message>
        <source>Saving %1</source>
        <translation>Speichere %1</translation>
    </message>
    <message>
        <source>Saved %1</source>
        <translation>%1 gespeichert</translation>
    </message>
    <message>
        <source>Unsaved edits</source>
        <translation>Ungespeicherte Änderungen</translation>
    </message>
    <message>
        <source>%1 has unsaved edits. Save them first?</source>
        <translation>%1 hat ungespeicherte Änderungen. Zuerst speichern?</translation>
    </message>
    <message>
        <source>A job is running: cancel it before quitting.</source>
        <translation>Eine Aufgabe läuft: brechen Sie sie vor dem Beenden ab.</translation>
    </message>
    <message>
        <source>%1[*] — Relume</source>
        <translation>%1[*] — Relume</translation>
    </message>
    <message>
        <source>No room open</source>
        <translation>Kein Raum geöffnet</translation>
    </message>
    <message>
        <source>free orbit</source>
        <translation>freie Umlaufansicht</translation>
    </message>
    <message>
        <source>photo camera</source>
        <translation>Kamera des Fotos</translation>
    </message>
    <message>
        <source>&amp;Language</source>
        <translation>&amp;Sprache</translation>
    </message>
    <message>
        <source>System language</source>
        <translation>Systemsprache</translation>
    </message>
    <message>
        <source>The language changes when Relume starts again.</source>
        <translation>Die Sprache wechselt beim nächsten Start von Relume.</translation>
    </message>
    <message>
        <source>Objects</source>
        <translation>Objekte</translation>
    </message>
    <message>
        <source>Add a &amp;virtual lamp (click a surface)</source>
        <translation>&amp;Virtuelle Leuchte hinzufügen (auf eine Fläche klicken)</translation>
    </message>
    <message>
        <source>Add a &amp;box (click a floor)</source>
        <translation>&amp;Kiste hinzufügen (auf einen Boden klicken)</translation>
    </message>
    <message>
        <source>&amp;Delete the selected lamp or object</source>
        <translation>Ausgewählte Leuchte oder Objekt &amp;löschen</translation>
    </message>
    <message>
        <source>Reference patches</source>
        <translation>Referenzfelder</translation>
    </message>
    <message>
        <source>Autosave failed: %1</source>
        <translation>Automatisches Speichern fehlgeschlagen: %1</translation>
    </message>
    <message>
        <source>Autosaving</source>
        <translation>Automatisches Speichern</translation>
    </message>
    <message>
        <source>Autosaved at %1</source>
        <translation>Automatisch gespeichert um %1</translation>
    </message>
    <message>
        <source>Recover unsaved edits</source>
        <translation>Nicht gespeicherte Änderungen wiederherstellen</translation>
    </message>
    <message>
        <source>Relume did not close properly. Recover the edits to %1 autosaved at %2?</source>
        <translation>Relume wurde nicht ordnungsgemäß beendet. Die um %2 automatisch gespeicherten Änderungen an %1 wiederherstellen?</translation>
    </message>
    <message>
        <source>Recovering %1</source>
        <translation>%1 wird wiederhergestellt</translation>
    </message>
    <message>
        <source>Recovered the autosaved edits of %1: save them to keep them.</source>
        <translation>Automatisch gespeicherte Änderungen an %1 wiederhergestellt: Speichern Sie sie, um sie zu behalten.</translation>
    </message>
    <message>
        <source>Cannot move the autosave %1 to %2</source>
        <translation>Die automatische Sicherung %1 kann nicht nach %2 verschoben werden</translation>
    </message>
    <message>
        <source>Occluded and &amp;frontier elements (§4.3)</source>
        <translation>Verdeckte und &amp;Grenzelemente (§4.3)</translation>
    </message>
    <message>
        <source>&amp;Interactive mesh (faster edits, coarser shadows)</source>
        <translation>&amp;Interaktives Netz (schnellere Änderungen, gröbere Schatten)</translation>
    </message>
    <message>
        <source>Building the interactive mesh</source>
        <translation>Interaktives Netz wird gebaut</translation>
    </message>
    <message>
        <source>Building the refined mesh</source>
        <translation>Verfeinertes Netz wird gebaut</translation>
    </message>
    <message>
        <source>%1 · %2 · %3, %4 leaves · %5 links · frame %6 ms · EV %7%8</source>
        <translation>%1 · %2 · %3, %4 Blätter · %5 Verbindungen · Bild %6 ms · LW %7%8</translation>
    </message>
    <message>
        <source>interactive mesh</source>
        <translation>interaktives Netz</translation>
    </message>
    <message>
        <source>refined mesh</source>
        <translation>verfeinertes Netz</translation>
    </message>
    <message>
        <source>Inspector</source>
        <translation>Inspektor</translation>
    </message>
    <message>
        <source>Photos</source>
        <translation>Fotos</translation>
    </message>
    <message>
        <source>Reconstruction</source>
        <translation>Rekonstruktion</translation>
    </message>
    <message>
        <source>Model from clicks</source>
        <translation>Modell aus Klicks</translation>
    </message>
    <message>
        <source>Sky</source>
        <translation>Himmel</translation>
    </message>
    <message>
        <source>Opened %1 (daylight: see the Sky panel)</source>
        <translation>%1 geöffnet (Tageslicht: siehe Himmel-Bereich)</translation>
    </message>
    <message>
        <source>Save the daylight room as a project</source>
        <translation>Den Tageslichtraum als Projekt speichern</translation>
    </message>
    <message>
        <source>A job is running: wait for it or cancel it, then save.</source>
        <translation>Eine Aufgabe läuft: warten Sie sie ab oder brechen Sie sie ab, dann speichern.</translation>
    </message>
</context>
<context>
    <name>relume::ObjectsPanel</name>
    <message>
        <source>New box</source>
        <translation>Neue Kiste</translation>
    </message>
    <message>
        <source> m</source>
        <translation> m</translation>
    </message>
    <message>
        <source>Albedo (diffuse reflectance) of the box</source>
        <translation>Albedo (diffuser Reflexionsgrad) der Kiste</translation>
    </message>
    <message>
        <source>Width</source>
        <translation>Breite</translation>
    </message>
    <message>
        <source>Depth</source>
        <translation>Tiefe</translation>
    </message>
    <message>
        <source>Height</source>
        <translation>Höhe</translation>
    </message>
    <message>
        <source>Albedo</source>
        <translation>Albedo</translation>
    </message>
    <message>
        <source>Place a box (click a floor)</source>
        <translation>Kiste aufstellen (auf einen Boden klicken)</translation>
    </message>
    <message>
        <source>Then click a floor or a table top in the viewport. Drag a box to move it along what it stands on.</source>
        <translation>Klicken Sie dann in der Ansicht auf einen Boden oder eine Tischplatte. Ziehen Sie eine Kiste, um sie auf ihrer Standfläche zu verschieben.</translation>
    </message>
    <message>
        <source>Objects in the room</source>
        <translation>Objekte im Raum</translation>
    </message>
    <message>
        <source>None yet.</source>
        <translation>Noch keine.</translation>
    </message>
    <message>
        <source>Albedo of the box</source>
        <translation>Albedo der Kiste</translation>
    </message>
    <message>
        <source>°</source>
        <translation>°</translation>
    </message>
    <message>
        <source>Turn about the vertical</source>
        <translation>Drehung um die Senkrechte</translation>
    </message>
    <message>
        <source>Delete</source>
        <translation>Löschen</translation>
    </message>
    <message>
        <source>Not turned: %1</source>
        <translation>Nicht gedreht: %1</translation>
    </message>
    <message>
        <source>Place an OBJ mesh...</source>
        <translation>OBJ-Netz aufstellen...</translation>
    </message>
    <message>
        <source>A mesh in metres, +Z up, with the albedo above; it stands where you click.</source>
        <translation>Ein Netz in Metern, +Z nach oben, mit der Albedo oben; es steht, wo Sie klicken.</translation>
    </message>
    <message>
        <source>Place an OBJ mesh</source>
        <translation>OBJ-Netz aufstellen</translation>
    </message>
    <message>
        <source>Wavefront OBJ (*.obj)</source>
        <translation>Wavefront OBJ (*.obj)</translation>
    </message>
    <message>
        <source>%1: %2 triangles; the radiosity engine takes meshes of up to %3.</source>
        <translation>%1: %2 Dreiecke; die Radiosity-Engine nimmt Netze mit bis zu %3.</translation>
    </message>
    <message>
        <source>Image-based object</source>
        <translation>Bildbasiertes Objekt</translation>
    </message>
    <message>
        <source>x </source>
        <translation>x </translation>
    </message>
    <message>
        <source>The mesh&apos;s units times this are metres</source>
        <translation>Die Einheiten des Netzes mal diesem Wert ergeben Meter</translation>
    </message>
    <message>
        <source>Scale</source>
        <translation>Maßstab</translation>
    </message>
    <message>
        <source>Place an image-based object...</source>
        <translation>Bildbasiertes Objekt platzieren...</translation>
    </message>
    <message>
        <source>An image fan (relume ibr-fan writes them) or a mesh of any size (OBJ, PLY, glTF), drawn from images relit by the room&apos;s lamps; it stands where you click.</source>
        <translation>Ein Bildfächer (relume ibr-fan schreibt sie) oder ein Netz beliebiger Größe (OBJ, PLY, glTF), gezeichnet aus Bildern, die die Lampen des Raums neu beleuchten; es steht dort, wo Sie klicken.</translation>
    </message>
    <message>
        <source>Place an image-based object</source>
        <translation>Bildbasiertes Objekt platzieren</translation>
    </message>
    <message>
        <source>Image fans and meshes (*.fan *.obj *.ply *.gltf *.glb)</source>
        <translation>Bildfächer und Netze (*.fan *.obj *.ply *.gltf *.glb)</translation>
    </message>
    <message>
        <source>Image-based objects in the room</source>
        <translation>Bildbasierte Objekte im Raum</translation>
    </message>
    <message>
        <source>Rendering the image fan of %1</source>
        <translation>Bildfächer von %1 wird gerendert</translation>
    </message>
    <message>
        <source>Another job is running: wait for it, or cancel it.</source>
        <translation>Eine andere Aufgabe läuft: warten Sie oder brechen Sie sie ab.</translation>
    </message>
    <message>
        <source>Scale (it keeps standing where it stands)</source>
        <translation>Maßstab (das Objekt bleibt stehen, wo es steht)</translation>
    </message>
    <message>
        <source>Not changed: %1</source>
        <translation>Nicht geändert: %1</translation>
    </message>
</context>
<context>
    <name>relume::PhotosPanel</name>
    <message>
        <source>Import folder...</source>
        <translation>Ordner importieren...</translation>
    </message>
    <message>
        <source>Import photos...</source>
        <translation>Fotos importieren...</translation>
    </message>
    <message>
        <source>Merge brackets to HDR</source>
        <translation>Reihen zu HDR zusammenführen</translation>
    </message>
    <message>
        <source>Each bracket of exposures becomes one radiance image (Debevec and Malik), beside its middle exposure: one photo per viewpoint, what reconstruction reads</source>
        <translation>Jede Belichtungsreihe wird ein Strahldichtebild (Debevec und Malik), neben ihrer mittleren Belichtung: ein Foto je Standpunkt, das die Rekonstruktion liest</translation>
    </message>
    <message>
        <source>No photos yet: import a folder of photos or brackets.</source>
        <translation>Noch keine Fotos: importieren Sie einen Ordner mit Fotos oder Belichtungsreihen.</translation>
    </message>
    <message>
        <source>Photo</source>
        <translation>Foto</translation>
    </message>
    <message>
        <source>Size</source>
        <translation>Größe</translation>
    </message>
    <message>
        <source>Camera</source>
        <translation>Kamera</translation>
    </message>
    <message>
        <source>Focal</source>
        <translation>Brennweite</translation>
    </message>
    <message>
        <source>Exposure</source>
        <translation>Belichtung</translation>
    </message>
    <message>
        <source>f/</source>
        <translation>f/</translation>
    </message>
    <message>
        <source>ISO</source>
        <translation>ISO</translation>
    </message>
    <message>
        <source>Bracket</source>
        <translation>Reihe</translation>
    </message>
    <message>
        <source>Histogram of the selected photo</source>
        <translation>Histogramm des gewählten Fotos</translation>
    </message>
    <message>
        <source>Recovered response (no bracket merged yet)</source>
        <translation>Ermittelte Kennlinie (noch keine Reihe zusammengeführt)</translation>
    </message>
    <message>
        <source> m</source>
        <translation> m</translation>
    </message>
    <message>
        <source>Inner corners</source>
        <translation>Innere Ecken</translation>
    </message>
    <message>
        <source>square</source>
        <translation>Feld</translation>
    </message>
    <message>
        <source>Calibrate from the selected photos</source>
        <translation>Aus den gewählten Fotos kalibrieren</translation>
    </message>
    <message>
        <source>Photos of a flat checkerboard from several angles: focal length, principal point and lens distortion (OpenCV), written to the capture&apos;s intrinsics.json</source>
        <translation>Fotos eines ebenen Schachbretts aus mehreren Winkeln: Brennweite, Hauptpunkt und Objektivverzeichnung (OpenCV), in die intrinsics.json der Aufnahme geschrieben</translation>
    </message>
    <message>
        <source>Not calibrated.</source>
        <translation>Nicht kalibriert.</translation>
    </message>
    <message>
        <source>Histogram</source>
        <translation>Histogramm</translation>
    </message>
    <message>
        <source>Response curve</source>
        <translation>Kennlinie</translation>
    </message>
    <message>
        <source>Calibration</source>
        <translation>Kalibrierung</translation>
    </message>
    <message>
        <source>Import a folder of photos</source>
        <translation>Einen Ordner mit Fotos importieren</translation>
    </message>
    <message>
        <source>Import photos</source>
        <translation>Fotos importieren</translation>
    </message>
    <message>
        <source>Photos (*.jpg *.jpeg *.png *.tif *.tiff *.exr)</source>
        <translation>Fotos (*.jpg *.jpeg *.png *.tif *.tiff *.exr)</translation>
    </message>
    <message>
        <source>%1 holds no photos (PNG, JPEG, TIFF or EXR).</source>
        <translation>%1 enthält keine Fotos (PNG, JPEG, TIFF oder EXR).</translation>
    </message>
    <message>
        <source>Importing photos: %1</source>
        <translation>Fotos werden importiert: %1</translation>
    </message>
    <message>
        <source>Imported the photos; %1 could not be read (see the list).</source>
        <translation>Fotos importiert; %1 nicht lesbar (siehe Liste).</translation>
    </message>
    <message>
        <source>Imported the photos.</source>
        <translation>Fotos importiert.</translation>
    </message>
    <message>
        <source>cannot be read</source>
        <translation>nicht lesbar</translation>
    </message>
    <message>
        <source>, radiance</source>
        <translation>, Strahldichte</translation>
    </message>
    <message>
        <source>%1 mm</source>
        <translation>%1 mm</translation>
    </message>
    <message>
        <source>(%1 mm eq.)</source>
        <translation>(%1 mm KB)</translation>
    </message>
    <message>
        <source>%1 EV</source>
        <translation>%1 LW</translation>
    </message>
    <message>
        <source>%1: %2 of %3</source>
        <translation>%1: %2 von %3</translation>
    </message>
    <message>
        <source>%1 photos, %2 viewpoints, brackets of several exposures: %3%4. Capture folder: %5</source>
        <translation>%1 Fotos, %2 Standpunkte, Belichtungsreihen: %3%4. Aufnahmeordner: %5</translation>
    </message>
    <message>
        <source>; cannot be read: %1</source>
        <translation>; nicht lesbar: %1</translation>
    </message>
    <message>
        <source>Histogram of %1%2</source>
        <translation>Histogramm von %1%2</translation>
    </message>
    <message>
        <source> (as shown, exposed)</source>
        <translation> (wie angezeigt, belichtet)</translation>
    </message>
    <message>
        <source>Recovered response, %1 exposures</source>
        <translation>Ermittelte Kennlinie, %1 Belichtungen</translation>
    </message>
    <message>
        <source>pixel value</source>
        <translation>Pixelwert</translation>
    </message>
    <message>
        <source>exposure</source>
        <translation>Belichtung</translation>
    </message>
    <message>
        <source>No 8-bit photos to merge.</source>
        <translation>Keine 8-Bit-Fotos zum Zusammenführen.</translation>
    </message>
    <message>
        <source>Merging brackets to HDR</source>
        <translation>Reihen werden zu HDR zusammengeführt</translation>
    </message>
    <message>
        <source>Brackets merged to HDR: %1; viewpoints in %2: %3</source>
        <translation>Zu HDR zusammengeführte Reihen: %1; Standpunkte in %2: %3</translation>
    </message>
    <message>
        <source>Select 3 or more photos of the checkerboard first.</source>
        <translation>Wählen Sie zuerst 3 oder mehr Fotos des Schachbretts.</translation>
    </message>
    <message>
        <source>Calibrating the camera</source>
        <translation>Kamera wird kalibriert</translation>
    </message>
    <message>
        <source>Reprojection error %1 px over %2 photos.
fx %3, fy %4, cx %5, cy %6 px; k1 %7, k2 %8, p1 %9, p2 %10.%11
Written to %12</source>
        <translation>Rückprojektionsfehler %1 px über %2 Fotos.
fx %3, fy %4, cx %5, cy %6 px; k1 %7, k2 %8, p1 %9, p2 %10.%11
Geschrieben nach %12</translation>
    </message>
    <message>
        <source>
No checkerboard found in: %1</source>
        <translation>
Kein Schachbrett gefunden in: %1</translation>
    </message>
    <message>
        <source>Cannot read %1: %2</source>
        <translation>%1 nicht lesbar: %2</translation>
    </message>
</context>
<context>
    <name>relume::ReconstructionPanel</name>
    <message>
        <source>Choose...</source>
        <translation>Wählen...</translation>
    </message>
    <message>
        <source>Choose a folder</source>
        <translation>Einen Ordner wählen</translation>
    </message>
    <message>
        <source>Photos</source>
        <translation>Fotos</translation>
    </message>
    <message>
        <source>One photo per viewpoint (8-bit; the merged photos of the Photos panel)</source>
        <translation>Ein Foto je Standpunkt (8 Bit; die zusammengeführten Fotos der Fotos-Leiste)</translation>
    </message>
    <message>
        <source>Workspace</source>
        <translation>Arbeitsordner</translation>
    </message>
    <message>
        <source>Where COLMAP&apos;s database and the model go (sparse/, workspace.json)</source>
        <translation>Wohin COLMAPs Datenbank und das Modell kommen (sparse/, workspace.json)</translation>
    </message>
    <message>
        <source>Run COLMAP</source>
        <translation>COLMAP starten</translation>
    </message>
    <message>
        <source>Features, matching and mapping on the CPU, as a job (Cancel stops COLMAP and writes nothing)</source>
        <translation>Merkmale, Zuordnung und Rekonstruktion auf der CPU, als Auftrag (Abbrechen beendet COLMAP und schreibt nichts)</translation>
    </message>
    <message>
        <source>No reconstruction yet.</source>
        <translation>Noch keine Rekonstruktion.</translation>
    </message>
    <message>
        <source>Photo</source>
        <translation>Foto</translation>
    </message>
    <message>
        <source>Registered</source>
        <translation>Registriert</translation>
    </message>
    <message>
        <source>Pick 2 points</source>
        <translation>2 Punkte wählen</translation>
    </message>
    <message>
        <source>Click two points of the reconstruction whose distance you measured in the room</source>
        <translation>Klicken Sie zwei Punkte der Rekonstruktion, deren Abstand Sie im Raum gemessen haben</translation>
    </message>
    <message>
        <source> m</source>
        <translation> m</translation>
    </message>
    <message>
        <source>Their distance in the room</source>
        <translation>Ihr Abstand im Raum</translation>
    </message>
    <message>
        <source>Pick 3 floor points</source>
        <translation>3 Bodenpunkte wählen</translation>
    </message>
    <message>
        <source>Click three points on the floor: it becomes z = 0, +z up</source>
        <translation>Klicken Sie drei Punkte auf dem Boden: er wird z = 0, +z nach oben</translation>
    </message>
    <message>
        <source>Apply metric frame</source>
        <translation>Metrischen Rahmen anwenden</translation>
    </message>
    <message>
        <source>Choose the folder of photos first.</source>
        <translation>Wählen Sie zuerst den Ordner der Fotos.</translation>
    </message>
    <message>
        <source>Choose a workspace folder first.</source>
        <translation>Wählen Sie zuerst einen Arbeitsordner.</translation>
    </message>
    <message>
        <source>Reconstructing with COLMAP</source>
        <translation>Rekonstruktion mit COLMAP</translation>
    </message>
    <message>
        <source>yes</source>
        <translation>ja</translation>
    </message>
    <message>
        <source>no: no pose found</source>
        <translation>nein: keine Pose gefunden</translation>
    </message>
    <message>
        <source>%1 of %2 photos registered; %3 points; mean reprojection error %4 px. Model: %5</source>
        <translation>%1 von %2 Fotos registriert; %3 Punkte; mittlerer Rückprojektionsfehler %4 px. Modell: %5</translation>
    </message>
    <message>
        <source>Scale points: %1; floor points: %2%3</source>
        <translation>Maßstabspunkte: %1; Bodenpunkte: %2%3</translation>
    </message>
    <message>
        <source> (click points in the view)</source>
        <translation> (Punkte in der Ansicht anklicken)</translation>
    </message>
    <message>
        <source>Pick two points and their distance, and three floor points, first.</source>
        <translation>Wählen Sie zuerst zwei Punkte mit ihrem Abstand und drei Bodenpunkte.</translation>
    </message>
    <message>
        <source>The model is in metres now, the floor at z = 0.</source>
        <translation>Das Modell ist jetzt in Metern, der Boden bei z = 0.</translation>
    </message>
    <message>
        <source>Align to known cameras...</source>
        <translation>An bekannten Kameras ausrichten...</translation>
    </message>
    <message>
        <source>Put the model in the frame of known cameras: a room, a project, or another reconstruction whose photos have the same names (their camera centres are matched)</source>
        <translation>Das Modell in das System bekannter Kameras bringen: ein Raum, ein Projekt oder eine andere Rekonstruktion mit gleich benannten Fotos (ihre Kamerazentren werden zugeordnet)</translation>
    </message>
    <message>
        <source>The room, project or reconstruction with the known cameras</source>
        <translation>Der Raum, das Projekt oder die Rekonstruktion mit den bekannten Kameras</translation>
    </message>
    <message>
        <source>Aligned to the %1 known cameras: camera centres %2 m apart (median), %3 m at most.</source>
        <translation>An den %1 bekannten Kameras ausgerichtet: Kamerazentren %2 m entfernt (Median), höchstens %3 m.</translation>
    </message>
</context>
<context>
    <name>relume::ReferencesPanel</name>
    <message>
        <source>Polygon</source>
        <translation>Polygon</translation>
    </message>
    <message>
        <source>Automatic</source>
        <translation>Automatisch</translation>
    </message>
    <message>
        <source>Yours</source>
        <translation>Ihres</translation>
    </message>
    <message>
        <source>Pick in the view</source>
        <translation>In der Ansicht wählen</translation>
    </message>
    <message>
        <source>Then click a texel of the selected polygon: its shadowed elements that match no unshadowed neighbour take that texel&apos;s reflectance.</source>
        <translation>Klicken Sie dann auf ein Texel des gewählten Polygons: Seine verschatteten Elemente ohne passenden unverschatteten Nachbarn übernehmen den Reflexionsgrad dieses Texels.</translation>
    </message>
    <message>
        <source>Back to the automatic choice for the selected polygon</source>
        <translation>Zurück zur automatischen Wahl für das gewählte Polygon</translation>
    </message>
    <message>
        <source>No room open.</source>
        <translation>Kein Raum geöffnet.</translation>
    </message>
    <message>
        <source>Removing the real shadows again</source>
        <translation>Reale Schatten werden erneut entfernt</translation>
    </message>
    <message>
        <source>Recompute</source>
        <translation>Neu berechnen</translation>
    </message>
    <message>
        <source>Recompute (changes pending)</source>
        <translation>Neu berechnen (Änderungen ausstehend)</translation>
    </message>
    <message>
        <source>Show occluded and frontier elements</source>
        <translation>Verdeckte und Grenzelemente zeigen</translation>
    </message>
    <message>
        <source>In the view: occluded elements in blue, the unshadowed frontier they take their colour from in yellow</source>
        <translation>In der Ansicht: verdeckte Elemente blau, die unverschattete Grenze, deren Farbe sie übernehmen, gelb</translation>
    </message>
    <message>
        <source>Reference patches as plane coordinates u, v of their polygon, in metres</source>
        <translation>Referenzflecken als Ebenenkoordinaten u, v ihres Polygons, in Metern</translation>
    </message>
    <message>
        <source>Paint a region</source>
        <translation>Bereich malen</translation>
    </message>
    <message>
        <source>Drag over a shadow of the selected polygon, then click the texel whose colour its occluded elements should take (for a shadow across two materials, say)</source>
        <translation>Ziehen Sie über einen Schatten des gewählten Polygons und klicken Sie dann das Texel, dessen Farbe seine verdeckten Elemente übernehmen sollen (etwa für einen Schatten über zwei Materialien)</translation>
    </message>
    <message>
        <source> m</source>
        <translation> m</translation>
    </message>
    <message>
        <source>Brush radius</source>
        <translation>Pinselradius</translation>
    </message>
    <message>
        <source>Clear regions</source>
        <translation>Bereiche löschen</translation>
    </message>
    <message>
        <source>Remove the regions painted on the selected polygon</source>
        <translation>Die auf dem gewählten Polygon gemalten Bereiche entfernen</translation>
    </message>
    <message>
        <source>%1 occluded elements: %2 keep the light the solution traced as blocked, %3 took a similar-coloured unshadowed neighbour as reference, %4 their polygon&apos;s reference patch, %5 a painted region&apos;s. Choose a patch, or paint a region, where a shadow left a wrong colour.</source>
        <translation>%1 verdeckte Elemente: %2 behalten das Licht, das die Lösung als verdeckt verfolgt hat, %3 nahmen einen ähnlich gefärbten unverschatteten Nachbarn als Referenz, %4 den Referenzfleck ihres Polygons, %5 den eines gemalten Bereichs. Wählen Sie einen Fleck oder malen Sie einen Bereich, wo ein Schatten eine falsche Farbe hinterließ.</translation>
    </message>
    <message>
        <source>not seen</source>
        <translation>nicht gesehen</translation>
    </message>
    <message>
        <source>1 region</source>
        <translation>1 Bereich</translation>
    </message>
    <message>
        <source>%1 regions</source>
        <translation>%1 Bereiche</translation>
    </message>
    <message>
        <source>Remove the real shadows again with these reference patches: step 2 of the polygons whose choices changed, as a job</source>
        <translation>Die echten Schatten mit diesen Referenzflächen erneut entfernen: Schritt 2 der Polygone, deren Wahl sich geändert hat, als Auftrag</translation>
    </message>
</context>
<context>
    <name>relume::SkyPanel</name>
    <message>
        <source>Sky</source>
        <translation>Himmel</translation>
    </message>
    <message>
        <source>The room&apos;s measured skies, and the fisheye images or folders you added</source>
        <translation>Die gemessenen Himmel des Raums und die hinzugefügten Fischaugenbilder oder Ordner</translation>
    </message>
    <message>
        <source>Image…</source>
        <translation>Bild…</translation>
    </message>
    <message>
        <source>An HDR fisheye taken outside looking up (equidistant, 180°, image up = +Y)</source>
        <translation>Ein HDR-Fischaugenbild, draußen nach oben aufgenommen (äquidistant, 180°, Bild oben = +Y)</translation>
    </message>
    <message>
        <source>Folder…</source>
        <translation>Ordner…</translation>
    </message>
    <message>
        <source>A folder of HDR fisheyes: a time-varying sky, played back in name order</source>
        <translation>Ein Ordner mit HDR-Fischaugenbildern: ein sich ändernder Himmel, nach Namen abgespielt</translation>
    </message>
    <message>
        <source>Method</source>
        <translation>Verfahren</translation>
    </message>
    <message>
        <source>Near-field (basis solutions)</source>
        <translation>Nahfeld (Basislösungen)</translation>
    </message>
    <message>
        <source>Interactive (irradiance volume)</source>
        <translation>Interaktiv (Bestrahlungsstärkevolumen)</translation>
    </message>
    <message>
        <source>Distant (sky at infinity, for comparison)</source>
        <translation>Fern (Himmel im Unendlichen, zum Vergleich)</translation>
    </message>
    <message>
        <source>Near-field: the objects solved into every basis. Interactive: the paper&apos;s irradiance volume and 64 samples through the windows, nothing solved again. Distant: the baseline without windows.</source>
        <translation>Nahfeld: die Objekte in jede Basis eingerechnet. Interaktiv: das Bestrahlungsstärkevolumen des Artikels und 64 Stichproben durch die Fenster, nichts wird neu gelöst. Fern: die Vergleichsmethode ohne Fenster.</translation>
    </message>
    <message>
        <source>Virtual objects</source>
        <translation>Virtuelle Objekte</translation>
    </message>
    <message>
        <source>File…</source>
        <translation>Datei…</translation>
    </message>
    <message>
        <source>Play</source>
        <translation>Abspielen</translation>
    </message>
    <message>
        <source>Play a folder&apos;s skies back, one frame after another</source>
        <translation>Die Himmel eines Ordners nacheinander abspielen</translation>
    </message>
    <message>
        <source>Original photo</source>
        <translation>Originalfoto</translation>
    </message>
    <message>
        <source>Show the photograph as taken, to compare</source>
        <translation>Das Foto wie aufgenommen zeigen, zum Vergleich</translation>
    </message>
    <message>
        <source>Sky image</source>
        <translation>Himmelsbild</translation>
    </message>
    <message>
        <source>HDR images (*.exr *.hdr)</source>
        <translation>HDR-Bilder (*.exr *.hdr)</translation>
    </message>
    <message>
        <source>Folder of sky images</source>
        <translation>Ordner mit Himmelsbildern</translation>
    </message>
    <message>
        <source>JSON (*.json)</source>
        <translation>JSON (*.json)</translation>
    </message>
    <message>
        <source>%1 (the photos&apos; sky)</source>
        <translation>%1 (der Himmel der Fotos)</translation>
    </message>
    <message>
        <source>None</source>
        <translation>Keine</translation>
    </message>
    <message>
        <source>As in variant %1</source>
        <translation>Wie in Variante %1</translation>
    </message>
    <message>
        <source>Preparing daylight for %1</source>
        <translation>Tageslicht für %1 wird vorbereitet</translation>
    </message>
    <message>
        <source>%1 holds no HDR sky image (.exr or .hdr)</source>
        <translation>%1 enthält kein HDR-Himmelsbild (.exr oder .hdr)</translation>
    </message>
    <message>
        <source>%1 (frames: %2)</source>
        <translation>%1 (Bilder: %2)</translation>
    </message>
    <message>
        <source>Open a daylight room (one whose scene lists measured skies and windows) to relight it under another sky.</source>
        <translation>Öffnen Sie einen Tageslichtraum (dessen Szene gemessene Himmel und Fenster enthält), um ihn unter einem anderen Himmel neu zu beleuchten.</translation>
    </message>
    <message>
        <source>%1 — measured skies: %2; reflectances estimated from the main photo under %3.</source>
        <translation>%1 — gemessene Himmel: %2; Reflexionsgrade aus dem Hauptfoto unter %3 geschätzt.</translation>
    </message>
    <message>
        <source>Relighting under %1</source>
        <translation>Neubeleuchtung unter %1</translation>
    </message>
    <message>
        <source>photo</source>
        <translation>Foto</translation>
    </message>
    <message>
        <source>The photograph as taken</source>
        <translation>Das Foto wie aufgenommen</translation>
    </message>
    <message>
        <source>Frame %1 of %2: %3, %4 s</source>
        <translation>Bild %1 von %2: %3, %4 s</translation>
    </message>
    <message>
        <source>%1, rendered in %2 s</source>
        <translation>%1, in %2 s berechnet</translation>
    </message>
    <message>
        <source>%1: the sun&apos;s pixels are clipped (at 65504, half float&apos;s largest value, or saturated): its light is understated and its colour shifted.</source>
        <translation>%1: die Pixel der Sonne sind abgeschnitten (bei 65504, dem größten Half-Float-Wert, oder gesättigt): ihr Licht wird unterschätzt und ihre Farbe verschoben.</translation>
    </message>
    <message>
        <source>Not rendered (%1): the image shows the setting before</source>
        <translation>Nicht berechnet (%1): das Bild zeigt die vorige Einstellung</translation>
    </message>
    <message>
        <source>Variant %1 left out: %2</source>
        <translation>Variante %1 weggelassen: %2</translation>
    </message>
    <message>
        <source>Lamps on beside the daylight</source>
        <translation>Lampen zusätzlich zum Tageslicht eingeschaltet</translation>
    </message>
    <message>
        <source>Check a lamp to switch it on at the radiance the room gives it (the photos are taken with the lamps off)</source>
        <translation>Eine Lampe ankreuzen, um sie mit der Leuchtdichte einzuschalten, die der Raum für sie angibt (die Fotos sind bei ausgeschalteten Lampen aufgenommen)</translation>
    </message>
    <message>
        <source>Lamp %1</source>
        <translation>Lampe %1</translation>
    </message>
    <message>
        <source>The room gives no radiance for this lamp, and a daylight photo (lamps off) cannot tell it</source>
        <translation>Der Raum gibt für diese Lampe keine Leuchtdichte an, und ein Tageslichtfoto (Lampen aus) kann sie nicht zeigen</translation>
    </message>
    <message>
        <source>Lamps (left out: the distant method is the sky alone)</source>
        <translation>Lampen (weggelassen: die ferne Methode ist nur der Himmel)</translation>
    </message>
    <message>
        <source>Lamps (left out: the interactive path lights virtual objects by daylight only; choose near-field)</source>
        <translation>Lampen (weggelassen: der interaktive Pfad beleuchtet virtuelle Objekte nur mit Tageslicht; Nahfeld wählen)</translation>
    </message>
    <message>
        <source>Virtual objects and lamps</source>
        <translation>Virtuelle Objekte und Lampen</translation>
    </message>
    <message>
        <source>A JSON file with virtual_objects (boxes or OBJ meshes with their albedo) and/or virtual_lights (lamps, lit with the near-field method)</source>
        <translation>Eine JSON-Datei mit virtual_objects (Quader oder OBJ-Netze mit ihrer Albedo) und/oder virtual_lights (Lampen, mit der Nahfeld-Methode beleuchtet)</translation>
    </message>
    <message>
        <source>The virtual lamps of %1 are left out: they are lit with the near-field method only</source>
        <translation>Die virtuellen Lampen von %1 werden weggelassen: sie leuchten nur mit der Nahfeld-Methode</translation>
    </message>
    <message>
        <source>Variant %1: its virtual lamps are left out: %2</source>
        <translation>Variante %1: ihre virtuellen Leuchten werden weggelassen: %2</translation>
    </message>
    <message>
        <source>The virtual lamps of %1 are left out: %2</source>
        <translation>Die virtuellen Leuchten von %1 werden weggelassen: %2</translation>
    </message>
    <message>
        <source>Saving %1</source>
        <translation>%1 wird gespeichert</translation>
    </message>
    <message>
        <source>Saved %1 (its daylight session kept: it opens without solving again)</source>
        <translation>%1 gespeichert (seine Tageslichtsitzung bleibt erhalten: es öffnet sich ohne neue Berechnung)</translation>
    </message>
    <message>
        <source>Drag a virtual object&apos;s cross to move it over the floor</source>
        <translation>Ziehen Sie das Kreuz eines virtuellen Objekts, um es über den Boden zu bewegen</translation>
    </message>
    <message>
        <source>the cursor points above the plane %1 stands on</source>
        <translation>der Zeiger zeigt über die Ebene, auf der %1 steht</translation>
    </message>
    <message>
        <source>the cursor points at %1, in front of the plane %2 stands on</source>
        <translation>der Zeiger zeigt auf %1, vor der Ebene, auf der %2 steht</translation>
    </message>
    <message>
        <source>Not moved: %1</source>
        <translation>Nicht verschoben: %1</translation>
    </message>
    <message>
        <source>%1, rendered in %2 ms</source>
        <translation>%1, in %2 ms gerendert</translation>
    </message>
    <message>
        <source>OpenGL</source>
        <translation>OpenGL</translation>
    </message>
    <message>
        <source>Draw the interactive method with OpenGL: a shadow map per sample through the windows and per direction of the sun&apos;s disc, as in the paper (the same light as the CPU path, drawn faster)</source>
        <translation>Die interaktive Methode mit OpenGL zeichnen: eine Schattenkarte je Stichprobe durch die Fenster und je Richtung der Sonnenscheibe, wie im Artikel (dasselbe Licht wie der CPU-Pfad, schneller gezeichnet)</translation>
    </message>
    <message>
        <source>OpenGL cannot draw the daylight view (%1): the CPU path draws it</source>
        <translation>OpenGL kann die Tageslichtansicht nicht zeichnen (%1): der CPU-Pfad zeichnet sie</translation>
    </message>
    <message>
        <source>Virtual lamp %1 of %2 is not saved: its photometric file %3 is gone</source>
        <translation>Die virtuelle Lampe %1 aus %2 wird nicht gespeichert: ihre photometrische Datei %3 fehlt</translation>
    </message>
    <message>
        <source>Lamps (left out: image-based objects are lit by daylight only)</source>
        <translation>Lampen (weggelassen: bildbasierte Objekte werden nur vom Tageslicht beleuchtet)</translation>
    </message>
    <message>
        <source>The image-based objects of %1 are left out: they are drawn by the near-field and interactive methods</source>
        <translation>Die bildbasierten Objekte von %1 werden weggelassen: sie werden von der Nahfeld- und der interaktiven Methode gezeichnet</translation>
    </message>
    <message>
        <source>The virtual lamps of %1 are left out: its image-based objects are lit by daylight only</source>
        <translation>Die virtuellen Lampen von %1 werden weggelassen: ihre bildbasierten Objekte werden nur vom Tageslicht beleuchtet</translation>
    </message>
    <message>
        <source>Image-based object %1 of %2 is not saved: its fan file %3 is gone</source>
        <translation>Das bildbasierte Objekt %1 von %2 wird nicht gespeichert: seine Bildfächer-Datei %3 ist verschwunden</translation>
    </message>
    <message>
        <source>%1: the sun&apos;s pixels are clipped (at 65504, half float&apos;s largest value, or saturated): its light is understated (its colour is taken from its pixels that did not clip).</source>
        <translation>%1: die Pixel der Sonne sind abgeschnitten (bei 65504, dem größten Half-Float-Wert, oder gesättigt): ihr Licht wird unterschätzt (ihre Farbe stammt aus ihren nicht abgeschnittenen Pixeln).</translation>
    </message>
    <message>
        <source>The lens the fisheye images and folders you add are read through: the ideal one (equidistant, 180°, the circle filling the image) or your sky camera&apos;s, calibrated with `relume calibrate --fisheye`</source>
        <translation>Das Objektiv, durch das hinzugefügte Fisheye-Bilder und -Ordner gelesen werden: das ideale (äquidistant, 180°, der Bildkreis füllt das Bild) oder das Ihrer Himmelskamera, kalibriert mit `relume calibrate --fisheye`</translation>
    </message>
    <message>
        <source>Calibrated lens…</source>
        <translation>Kalibriertes Objektiv…</translation>
    </message>
    <message>
        <source>Calibrated fisheye lens</source>
        <translation>Kalibriertes Fisheye-Objektiv</translation>
    </message>
    <message>
        <source>Ideal lens (equidistant, 180°)</source>
        <translation>Ideales Objektiv (äquidistant, 180°)</translation>
    </message>
    <message>
        <source>Lens: ideal</source>
        <translation>Objektiv: ideal</translation>
    </message>
    <message>
        <source>Lens: %1</source>
        <translation>Objektiv: %1</translation>
    </message>
    <message>
        <source>%1 (read through the lens %2)</source>
        <translation>%1 (gelesen durch das Objektiv %2)</translation>
    </message>
</context>
<context>
    <name>relume::ViewportWidget</name>
    <message>
        <source>Open a room or a project (File &gt; Open) to relight it.</source>
        <translation>Öffnen Sie einen Raum oder ein Projekt (Datei &gt; Öffnen), um ihn neu zu beleuchten.</translation>
    </message>
    <message>
        <source>luminance</source>
        <translation>Leuchtdichte</translation>
    </message>
</context>
</TS>
