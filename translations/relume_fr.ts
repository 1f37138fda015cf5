<?xml version="1.0" encoding="utf-8"?>
<!DOCTYPE TS>
<TS version="2.1" language="fr_FR">
<context>
    <name>relume::ClickPhotoView</name>
    <message>
        <source>No photo</source>
        <translation>Aucune photo</translation>
    </message>
</context>
<context>
    <name>relume::ClicksPanel</name>
    <message>
        <source>Workspace</source>
        <translation>Espace de travail</translation>
    </message>
    <message>
        <source>A reconstruction workspace or COLMAP model folder (cameras), or a new folder: the clicks are kept there as clicks.json</source>
        <translation>Un espace de travail de reconstruction ou un dossier de modèle COLMAP (caméras), ou un nouveau dossier : les clics y sont gardés dans clicks.json</translation>
    </message>
    <message>
        <source>Choose...</source>
        <translation>Choisir...</translation>
    </message>
    <message>
        <source>Photos</source>
        <translation>Photos</translation>
    </message>
    <message>
        <source>from the workspace</source>
        <translation>de l&apos;espace de travail</translation>
    </message>
    <message>
        <source>Open</source>
        <translation>Ouvrir</translation>
    </message>
    <message>
        <source>Choose the workspace</source>
        <translation>Choisir l&apos;espace de travail</translation>
    </message>
    <message>
        <source>The photo to click corners in</source>
        <translation>La photo où cliquer les coins</translation>
    </message>
    <message>
        <source>A second photo: proposals for the corner appear here</source>
        <translation>Une seconde photo : les propositions pour le coin y apparaissent</translation>
    </message>
    <message>
        <source>Fit</source>
        <translation>Ajuster</translation>
    </message>
    <message>
        <source>1:1</source>
        <translation>1:1</translation>
    </message>
    <message>
        <source>The whole photo (F)</source>
        <translation>La photo entière (F)</translation>
    </message>
    <message>
        <source>One photo pixel per screen pixel</source>
        <translation>Un pixel de la photo par pixel d&apos;écran</translation>
    </message>
    <message>
        <source>Point</source>
        <translation>Point</translation>
    </message>
    <message>
        <source>Clicked in</source>
        <translation>Cliqué dans</translation>
    </message>
    <message>
        <source>Error</source>
        <translation>Erreur</translation>
    </message>
    <message>
        <source>Depth</source>
        <translation>Profondeur</translation>
    </message>
    <message>
        <source>New point</source>
        <translation>Nouveau point</translation>
    </message>
    <message>
        <source>The next click starts a new point (N)</source>
        <translation>Le prochain clic commence un nouveau point (N)</translation>
    </message>
    <message>
        <source>Delete</source>
        <translation>Supprimer</translation>
    </message>
    <message>
        <source>Deletes the selected points (and the polygons left with fewer than 3 corners)</source>
        <translation>Supprime les points sélectionnés (et les polygones laissés avec moins de 3 coins)</translation>
    </message>
    <message>
        <source>Merge</source>
        <translation>Fusionner</translation>
    </message>
    <message>
        <source>The second picked point&apos;s clicks go to the first; polygons follow</source>
        <translation>Les clics du second point choisi vont au premier ; les polygones suivent</translation>
    </message>
    <message>
        <source>Pick two points to merge (Ctrl+click).</source>
        <translation>Choisissez deux points à fusionner (Ctrl+clic).</translation>
    </message>
    <message>
        <source> m</source>
        <translation> m</translation>
    </message>
    <message>
        <source>Measured</source>
        <translation>Mesuré</translation>
    </message>
    <message>
        <source>The current point&apos;s measured position (a control point when it is clicked too); with no point current, a new point only measured (a corner no photo shows)</source>
        <translation>La position mesurée du point courant (un point de contrôle s&apos;il est aussi cliqué) ; sans point courant, un nouveau point seulement mesuré (un coin qu&apos;aucune photo ne montre)</translation>
    </message>
    <message>
        <source>Clear</source>
        <translation>Effacer</translation>
    </message>
    <message>
        <source>Forget the current point&apos;s measured position</source>
        <translation>Oublier la position mesurée du point courant</translation>
    </message>
    <message>
        <source>Polygon</source>
        <translation>Polygone</translation>
    </message>
    <message>
        <source>Corners</source>
        <translation>Coins</translation>
    </message>
    <message>
        <source>Group</source>
        <translation>Groupe</translation>
    </message>
    <message>
        <source>Lamp</source>
        <translation>Lampe</translation>
    </message>
    <message>
        <source>Rectangle</source>
        <translation>Rectangle</translation>
    </message>
    <message>
        <source>Plane</source>
        <translation>Plan</translation>
    </message>
    <message>
        <source>Double-click a name, group, lamp name or plane key to change it. Tick Lamp for a lamp (its name: the text, else the polygon&apos;s); polygons with the same plane key share one plane</source>
        <translation>Double-cliquez un nom, un groupe, un nom de lampe ou une clé de plan pour le changer. Cochez Lampe pour une lampe (son nom : le texte, sinon celui du polygone) ; les polygones de même clé de plan partagent un plan</translation>
    </message>
    <message>
        <source>name (optional)</source>
        <translation>nom (facultatif)</translation>
    </message>
    <message>
        <source>The new polygon&apos;s name</source>
        <translation>Le nom du nouveau polygone</translation>
    </message>
    <message>
        <source>Polygon from picked</source>
        <translation>Polygone des points choisis</translation>
    </message>
    <message>
        <source>A polygon through the picked points, in the order picked (P)</source>
        <translation>Un polygone par les points choisis, dans l&apos;ordre choisi (P)</translation>
    </message>
    <message>
        <source>Delete polygon</source>
        <translation>Supprimer le polygone</translation>
    </message>
    <message>
        <source>Undo</source>
        <translation>Annuler</translation>
    </message>
    <message>
        <source>Redo</source>
        <translation>Rétablir</translation>
    </message>
    <message>
        <source>Project</source>
        <translation>Projet</translation>
    </message>
    <message>
        <source>The Relume project the model is written to</source>
        <translation>Le projet Relume où le modèle est écrit</translation>
    </message>
    <message>
        <source>Focal length</source>
        <translation>Focale</translation>
    </message>
    <message>
        <source> px</source>
        <translation> px</translation>
    </message>
    <message>
        <source>from EXIF / calibration</source>
        <translation>EXIF / étalonnage</translation>
    </message>
    <message>
        <source>Without a reconstruction: the camera&apos;s focal length in pixels (the Photos panel&apos;s calibration is used when there is one)</source>
        <translation>Sans reconstruction : la focale de l&apos;appareil en pixels (l&apos;étalonnage du panneau Photos sert s&apos;il existe)</translation>
    </message>
    <message>
        <source>Build model</source>
        <translation>Construire le modèle</translation>
    </message>
    <message>
        <source>Triangulate the points, fit the polygons, write the project and preprocess it</source>
        <translation>Trianguler les points, ajuster les polygones, écrire le projet et le prétraiter</translation>
    </message>
    <message>
        <source>Open a workspace to click corners in its photos.</source>
        <translation>Ouvrez un espace de travail pour cliquer les coins dans ses photos.</translation>
    </message>
    <message>
        <source>Choose a workspace folder first.</source>
        <translation>Choisissez d&apos;abord un dossier d&apos;espace de travail.</translation>
    </message>
    <message>
        <source>Cannot create the folder %1.</source>
        <translation>Impossible de créer le dossier %1.</translation>
    </message>
    <message>
        <source>%1 photos from %2</source>
        <translation>%1 photos de %2</translation>
    </message>
    <message>
        <source>New point %1</source>
        <translation>Nouveau point %1</translation>
    </message>
    <message>
        <source>Click %1 in %2</source>
        <translation>Clic de %1 dans %2</translation>
    </message>
    <message>
        <source>Accept the match of %1 in %2</source>
        <translation>Accepter la correspondance de %1 dans %2</translation>
    </message>
    <message>
        <source>Move %1 in %2</source>
        <translation>Déplacer %1 dans %2</translation>
    </message>
    <message>
        <source>Delete point %1</source>
        <translation>Supprimer le point %1</translation>
    </message>
    <message>
        <source>Delete %1 points</source>
        <translation>Supprimer %1 points</translation>
    </message>
    <message>
        <source>Merge %1 into %2</source>
        <translation>Fusionner %1 dans %2</translation>
    </message>
    <message>
        <source>Measure %1</source>
        <translation>Mesurer %1</translation>
    </message>
    <message>
        <source>Forget the measure of %1</source>
        <translation>Oublier la mesure de %1</translation>
    </message>
    <message>
        <source>New measured point %1</source>
        <translation>Nouveau point mesuré %1</translation>
    </message>
    <message>
        <source>Pick three or more corners in order first (Ctrl+click them, or select them in the list).</source>
        <translation>Choisissez d&apos;abord trois coins ou plus dans l&apos;ordre (Ctrl+clic, ou sélection dans la liste).</translation>
    </message>
    <message>
        <source>There is a polygon called %1 already.</source>
        <translation>Un polygone nommé %1 existe déjà.</translation>
    </message>
    <message>
        <source>New polygon %1</source>
        <translation>Nouveau polygone %1</translation>
    </message>
    <message>
        <source>Delete polygon %1</source>
        <translation>Supprimer le polygone %1</translation>
    </message>
    <message>
        <source>%1 is a lamp</source>
        <translation>%1 est une lampe</translation>
    </message>
    <message>
        <source>%1 is not a lamp</source>
        <translation>%1 n&apos;est pas une lampe</translation>
    </message>
    <message>
        <source>A polygon needs a name of its own.</source>
        <translation>Un polygone a besoin de son propre nom.</translation>
    </message>
    <message>
        <source>Rename %1 to %2</source>
        <translation>Renommer %1 en %2</translation>
    </message>
    <message>
        <source>%1 in group %2</source>
        <translation>%1 dans le groupe %2</translation>
    </message>
    <message>
        <source>%1 is a rectangle</source>
        <translation>%1 est un rectangle</translation>
    </message>
    <message>
        <source>%1 is not a rectangle</source>
        <translation>%1 n&apos;est pas un rectangle</translation>
    </message>
    <message>
        <source>%1 shares plane %2</source>
        <translation>%1 partage le plan %2</translation>
    </message>
    <message>
        <source>clicked in one photo: click it in another</source>
        <translation>cliqué dans une photo : cliquez-le dans une autre</translation>
    </message>
    <message>
        <source>no cameras yet</source>
        <translation>pas encore de caméras</translation>
    </message>
    <message>
        <source>measured (%1, %2, %3)</source>
        <translation>mesuré (%1, %2, %3)</translation>
    </message>
    <message>
        <source>%1 px</source>
        <translation>%1 px</translation>
    </message>
    <message>
        <source>weak (%1°)</source>
        <translation>faible (%1°)</translation>
    </message>
    <message>
        <source>good (%1°)</source>
        <translation>bonne (%1°)</translation>
    </message>
    <message>
        <source>Clicked in photos taken from nearly the same direction: click it in a photo further to the side</source>
        <translation>Cliqué dans des photos prises presque de la même direction : cliquez-le dans une photo plus sur le côté</translation>
    </message>
    <message>
        <source>measured</source>
        <translation>mesuré</translation>
    </message>
    <message>
        <source>%1 points, %2 polygons; %3. Saved in %4</source>
        <translation>%1 points, %2 polygones ; %3. Enregistré dans %4</translation>
    </message>
    <message>
        <source>cameras from the reconstruction</source>
        <translation>caméras de la reconstruction</translation>
    </message>
    <message>
        <source>no cameras yet (solved from the clicks when building)</source>
        <translation>pas encore de caméras (résolues à partir des clics à la construction)</translation>
    </message>
    <message>
        <source>Open a workspace: its photos appear here side by side.</source>
        <translation>Ouvrez un espace de travail : ses photos apparaissent ici côte à côte.</translation>
    </message>
    <message>
        <source>Click a corner in either photo to start a point. Ctrl+click points to pick polygon corners in order.</source>
        <translation>Cliquez un coin dans l&apos;une des photos pour commencer un point. Ctrl+clic sur des points pour choisir les coins d&apos;un polygone dans l&apos;ordre.</translation>
    </message>
    <message>
        <source>Point %1: click it in the other photo; drag a cross to move it. N starts a new point.</source>
        <translation>Point %1 : cliquez-le dans l&apos;autre photo ; faites glisser une croix pour la déplacer. N commence un nouveau point.</translation>
    </message>
    <message>
        <source>Open a workspace and click the corners first.</source>
        <translation>Ouvrez d&apos;abord un espace de travail et cliquez les coins.</translation>
    </message>
    <message>
        <source>Choose where the project goes first.</source>
        <translation>Choisissez d&apos;abord où va le projet.</translation>
    </message>
    <message>
        <source>Building the model from the clicks</source>
        <translation>Construction du modèle à partir des clics</translation>
    </message>
    <message>
        <source>Warning: %1</source>
        <translation>Attention : %1</translation>
    </message>
    <message>
        <source>%1 points (largest reprojection error %2 px), %3 polygons, %4 lamps: %5</source>
        <translation>%1 points (plus grande erreur de reprojection %2 px), %3 polygones, %4 lampes : %5</translation>
    </message>
    <message>
        <source>Scale</source>
        <translation>Échelle</translation>
    </message>
    <message>
        <source>point</source>
        <translation>point</translation>
    </message>
    <message>
        <source>floor points</source>
        <translation>points du sol</translation>
    </message>
    <message>
        <source>Without a reconstruction and without three measured clicked points: two points, their distance, and three or more floor points (names, comma-separated) set the metric frame</source>
        <translation>Sans reconstruction ni trois points cliqués mesurés : deux points, leur distance, et trois points du sol ou plus (noms séparés par des virgules) fixent le repère métrique</translation>
    </message>
    <message>
        <source>Point %1: click a ring to accept that proposal (Enter: the best; 1-3), or click the corner where it is (Shift+click: exactly there, even on a ring). N starts a new point.</source>
        <translation>Point %1 : cliquez un anneau pour accepter cette proposition (Entrée : la meilleure ; 1-3), ou cliquez le coin là où il est (Maj+clic : exactement là, même sur un anneau). N commence un nouveau point.</translation>
    </message>
    <message>
        <source>Points and polygons</source>
        <translation>Points et polygones</translation>
    </message>
    <message>
        <source>The points and polygons in 3-D with the cameras (drag to orbit, wheel to zoom)</source>
        <translation>Les points et les polygones en 3-D avec les caméras (glisser pour tourner, molette pour zoomer)</translation>
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
        <translation>lampe %1</translation>
    </message>
    <message>
        <source>add %1</source>
        <translation>ajout de %1</translation>
    </message>
    <message>
        <source>remove %1</source>
        <translation>suppression de %1</translation>
    </message>
    <message>
        <source>move %1</source>
        <translation>déplacement de %1</translation>
    </message>
    <message>
        <source>change %1</source>
        <translation>modification de %1</translation>
    </message>
    <message>
        <source>reference patch of %1</source>
        <translation>patch de référence de %1</translation>
    </message>
    <message>
        <source>automatic reference of %1</source>
        <translation>référence automatique de %1</translation>
    </message>
    <message>
        <source>reference region on %1</source>
        <translation>région de référence sur %1</translation>
    </message>
    <message>
        <source>no reference regions on %1</source>
        <translation>aucune région de référence sur %1</translation>
    </message>
</context>
<context>
    <name>relume::EditTool</name>
    <message>
        <source>Click a surface to put a virtual lamp 2 cm in front of it.</source>
        <translation>Cliquez sur une surface pour y placer une lampe virtuelle à 2 cm devant elle.</translation>
    </message>
    <message>
        <source>Click a floor or a table top to stand the box on it.</source>
        <translation>Cliquez sur un sol ou un plateau de table pour y poser la boîte.</translation>
    </message>
    <message>
        <source>No surface there: click on the room.</source>
        <translation>Aucune surface ici : cliquez sur la pièce.</translation>
    </message>
    <message>
        <source>Lamp</source>
        <translation>Lampe</translation>
    </message>
    <message>
        <source>Added %1 (%2 ms).</source>
        <translation>%1 ajouté (%2 ms).</translation>
    </message>
    <message>
        <source>Objects stand on floors and tables: click a horizontal surface.</source>
        <translation>Les objets se posent sur les sols et les tables : cliquez sur une surface horizontale.</translation>
    </message>
    <message>
        <source>Box</source>
        <translation>Boîte</translation>
    </message>
    <message>
        <source>Not moved: %1</source>
        <translation>Non déplacé : %1</translation>
    </message>
    <message>
        <source>Click a texel of %1 whose colour its shadowed parts should take.</source>
        <translation>Cliquez sur un texel de %1 dont ses parties ombrées doivent prendre la couleur.</translation>
    </message>
    <message>
        <source>That is not %1: click on it, or press Esc.</source>
        <translation>Ce n&apos;est pas %1 : cliquez dessus, ou appuyez sur Échap.</translation>
    </message>
    <message>
        <source>Reference patch of %1 set: recompute to see it.</source>
        <translation>Patch de référence de %1 choisi : recalculez pour le voir.</translation>
    </message>
    <message>
        <source>Click a floor or a table top to stand %1 on it.</source>
        <translation>Cliquez sur un sol ou un plateau de table pour y poser %1.</translation>
    </message>
    <message>
        <source>%1 cannot stand there: %2</source>
        <translation>%1 ne peut pas être posé ici : %2</translation>
    </message>
    <message>
        <source>Paint over the shadowed part of %1 (drag); then click the texel it should take its colour from.</source>
        <translation>Peignez la partie ombrée de %1 (glisser) ; puis cliquez le texel dont elle doit prendre la couleur.</translation>
    </message>
    <message>
        <source>Reference region painted on %1: recompute to see it.</source>
        <translation>Région de référence peinte sur %1 : recalculez pour la voir.</translation>
    </message>
    <message>
        <source>Now click the texel of %1 whose colour the painted shadow should take.</source>
        <translation>Cliquez maintenant le texel de %1 dont l&apos;ombre peinte doit prendre la couleur.</translation>
    </message>
    <message>
        <source>Added %1.</source>
        <translation>%1 ajouté.</translation>
    </message>
</context>
<context>
    <name>relume::InspectorPanel</name>
    <message>
        <source>Radiosity B</source>
        <translation>Radiosité B</translation>
    </message>
    <message>
        <source>Irradiance E</source>
        <translation>Éclairement E</translation>
    </message>
    <message>
        <source>Display factor D</source>
        <translation>Facteur d&apos;affichage D</translation>
    </message>
    <message>
        <source>Ratio B / D</source>
        <translation>Rapport B / D</translation>
    </message>
    <message>
        <source>Reflectance</source>
        <translation>Réflectance</translation>
    </message>
    <message>
        <source>Shadow-free texture T_final</source>
        <translation>Texture sans ombres T_final</translation>
    </message>
    <message>
        <source>Element level</source>
        <translation>Niveau de l&apos;élément</translation>
    </message>
    <message>
        <source>Visibility from a lamp</source>
        <translation>Visibilité depuis une lampe</translation>
    </message>
    <message>
        <source>What colours the elements (RGB quantities: the mean of R, G and B)</source>
        <translation>Ce qui colore les éléments (grandeurs RVB : la moyenne de R, V et B)</translation>
    </message>
    <message>
        <source>The lamp whose links are classed: visible, partly hidden, or hidden</source>
        <translation>La lampe dont les liens sont classés : visibles, en partie cachés ou cachés</translation>
    </message>
    <message>
        <source>Show the elements of one polygon only</source>
        <translation>N&apos;afficher que les éléments d&apos;un polygone</translation>
    </message>
    <message>
        <source>Viewport&apos;s mesh</source>
        <translation>Maillage de la vue</translation>
    </message>
    <message>
        <source>Other mesh</source>
        <translation>Autre maillage</translation>
    </message>
    <message>
        <source>The refined and the interactive mesh: the other one is a second session, built as a job</source>
        <translation>Le maillage raffiné et le maillage interactif : l&apos;autre est une seconde session, construite en tâche de fond</translation>
    </message>
    <message>
        <source>Colour by</source>
        <translation>Couleur selon</translation>
    </message>
    <message>
        <source>Polygon</source>
        <translation>Polygone</translation>
    </message>
    <message>
        <source>Role</source>
        <translation>Rôle</translation>
    </message>
    <message>
        <source>Source</source>
        <translation>Source</translation>
    </message>
    <message>
        <source>Receiver</source>
        <translation>Récepteur</translation>
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
        <translation>Type</translation>
    </message>
    <message>
        <source>Oracle error</source>
        <translation>Erreur de l&apos;oracle</translation>
    </message>
    <message>
        <source>The links the picked element holds: those it gathers by, and those it sends by</source>
        <translation>Les liens de l&apos;élément choisi : ceux par lesquels il reçoit, et ceux par lesquels il émet</translation>
    </message>
    <message>
        <source>Links of the picked element</source>
        <translation>Liens de l&apos;élément choisi</translation>
    </message>
    <message>
        <source>Counts per polygon</source>
        <translation>Comptes par polygone</translation>
    </message>
    <message>
        <source>All polygons</source>
        <translation>Tous les polygones</translation>
    </message>
    <message>
        <source>No room open.</source>
        <translation>Aucune pièce ouverte.</translation>
    </message>
    <message>
        <source>Light from %1</source>
        <translation>Lumière de %1</translation>
    </message>
    <message>
        <source>VISIBLE</source>
        <translation>VISIBLE</translation>
    </message>
    <message>
        <source>INVISIBLE</source>
        <translation>INVISIBLE</translation>
    </message>
    <message>
        <source>PARTIAL</source>
        <translation>PARTIELLE</translation>
    </message>
    <message>
        <source>%1: %2 elements shown of %3 leaves; %4 links in the engine</source>
        <translation>%1 : %2 éléments affichés sur %3 feuilles ; %4 liens dans le moteur</translation>
    </message>
    <message>
        <source>interactive mesh</source>
        <translation>maillage interactif</translation>
    </message>
    <message>
        <source>refined mesh</source>
        <translation>maillage raffiné</translation>
    </message>
    <message>
        <source>cluster %1</source>
        <translation>groupe %1</translation>
    </message>
    <message>
        <source>%1 #%2 (level %3)</source>
        <translation>%1 n° %2 (niveau %3)</translation>
    </message>
    <message>
        <source>visible</source>
        <translation>visible</translation>
    </message>
    <message>
        <source>invisible</source>
        <translation>invisible</translation>
    </message>
    <message>
        <source>partial</source>
        <translation>partielle</translation>
    </message>
    <message>
        <source>gathers</source>
        <translation>reçoit</translation>
    </message>
    <message>
        <source>sends</source>
        <translation>émet</translation>
    </message>
    <message>
        <source>Elements, leaves and links per polygon (the 6 with the most links)</source>
        <translation>Éléments, feuilles et liens par polygone (les 6 qui ont le plus de liens)</translation>
    </message>
    <message>
        <source>elements</source>
        <translation>éléments</translation>
    </message>
    <message>
        <source>leaves</source>
        <translation>feuilles</translation>
    </message>
    <message>
        <source>links received</source>
        <translation>liens reçus</translation>
    </message>
    <message>
        <source>Building the other mesh for the inspector</source>
        <translation>Construction de l&apos;autre maillage pour l&apos;inspecteur</translation>
    </message>
</context>
<context>
    <name>relume::JobRunner</name>
    <message>
        <source>Cancelled; nothing was changed.</source>
        <translation>Annulé ; rien n&apos;a été modifié.</translation>
    </message>
</context>
<context>
    <name>relume::LightsPanel</name>
    <message>
        <source>No room open.</source>
        <translation>Aucune pièce ouverte.</translation>
    </message>
    <message>
        <source>Lamp strengths estimated by the preprocess (%1). Drag a slider to dim or boost a lamp; untick to switch it off.</source>
        <translation>Intensités des lampes estimées par le prétraitement (%1). Faites glisser un curseur pour atténuer ou renforcer une lampe ; décochez pour l&apos;éteindre.</translation>
    </message>
    <message>
        <source>Lamp %1</source>
        <translation>Lampe %1</translation>
    </message>
    <message>
        <source>On</source>
        <translation>Allumée</translation>
    </message>
    <message>
        <source>Intensity, 0-400 % of the photographed lamp</source>
        <translation>Intensité, 0 à 400 % de la lampe photographiée</translation>
    </message>
    <message>
        <source>Colour of the lamp</source>
        <translation>Couleur de la lampe</translation>
    </message>
    <message>
        <source>its photometric file&apos;s flux</source>
        <translation>le flux de son fichier photométrique</translation>
    </message>
    <message>
        <source>Emits as %1 says (%2, %3 lm)</source>
        <translation>Émet comme l&apos;indique %1 (%2, %3 lm)</translation>
    </message>
    <message>
        <source>measured in the HDR photo</source>
        <translation>mesurée dans la photo HDR</translation>
    </message>
    <message>
        <source>least-squares fit</source>
        <translation>ajustement aux moindres carrés</translation>
    </message>
    <message>
        <source>Eq. 2, all lamps equal</source>
        <translation>éq. 2, toutes les lampes égales</translation>
    </message>
    <message>
        <source>Estimate: %1, %2, %3 W/m² (%4)</source>
        <translation>Estimation : %1, %2, %3 W/m² (%4)</translation>
    </message>
    <message>
        <source>Virtual lamps</source>
        <translation>Lampes virtuelles</translation>
    </message>
    <message>
        <source>Add a lamp (click a surface)</source>
        <translation>Ajouter une lampe (cliquez sur une surface)</translation>
    </message>
    <message>
        <source>Then click a surface in the viewport: a 30 cm lamp appears 2 cm in front of it, facing away from it. Drag it to move it along that surface.</source>
        <translation>Cliquez ensuite sur une surface dans la vue : une lampe de 30 cm apparaît à 2 cm devant elle, tournée vers l&apos;extérieur. Faites-la glisser pour la déplacer le long de cette surface.</translation>
    </message>
    <message>
        <source>Power, 0-400 % of the brightest real lamp</source>
        <translation>Puissance, 0 à 400 % de la lampe réelle la plus puissante</translation>
    </message>
    <message>
        <source> m</source>
        <translation> m</translation>
    </message>
    <message>
        <source>Width of the square lamp</source>
        <translation>Largeur de la lampe carrée</translation>
    </message>
    <message>
        <source>drop </source>
        <translation>suspension </translation>
    </message>
    <message>
        <source>Distance from the surface it was put on (a pendant&apos;s suspension)</source>
        <translation>Distance à la surface où elle a été posée (suspension d&apos;un luminaire)</translation>
    </message>
    <message>
        <source>Delete</source>
        <translation>Supprimer</translation>
    </message>
    <message>
        <source>Not moved: %1</source>
        <translation>Non déplacé : %1</translation>
    </message>
</context>
<context>
    <name>relume::MainWindow</name>
    <message>
        <source>Lights</source>
        <translation>Éclairage</translation>
    </message>
    <message>
        <source>Cancel</source>
        <translation>Annuler</translation>
    </message>
    <message>
        <source>Relume</source>
        <translation>Relume</translation>
    </message>
    <message>
        <source>&amp;File</source>
        <translation>&amp;Fichier</translation>
    </message>
    <message>
        <source>&amp;Open...</source>
        <translation>&amp;Ouvrir...</translation>
    </message>
    <message>
        <source>Open a room or a Relume project</source>
        <translation>Ouvrir une pièce ou un projet Relume</translation>
    </message>
    <message>
        <source>Open &amp;OBJ + JSON...</source>
        <translation>Ouvrir &amp;OBJ + JSON...</translation>
    </message>
    <message>
        <source>Open a room</source>
        <translation>Ouvrir une pièce</translation>
    </message>
    <message>
        <source>Room geometry (*.obj)</source>
        <translation>Géométrie de la pièce (*.obj)</translation>
    </message>
    <message>
        <source>Open &amp;Recent</source>
        <translation>Ouvrir un fichier &amp;récent</translation>
    </message>
    <message>
        <source>&amp;Save</source>
        <translation>&amp;Enregistrer</translation>
    </message>
    <message>
        <source>Save the project as</source>
        <translation>Enregistrer le projet sous</translation>
    </message>
    <message>
        <source>Save &amp;As...</source>
        <translation>Enregistrer &amp;sous...</translation>
    </message>
    <message>
        <source>&amp;Quit</source>
        <translation>&amp;Quitter</translation>
    </message>
    <message>
        <source>&amp;Edit</source>
        <translation>É&amp;dition</translation>
    </message>
    <message>
        <source>&amp;Undo</source>
        <translation>&amp;Annuler</translation>
    </message>
    <message>
        <source>&amp;Redo</source>
        <translation>&amp;Rétablir</translation>
    </message>
    <message>
        <source>&amp;View</source>
        <translation>&amp;Affichage</translation>
    </message>
    <message>
        <source>&amp;Relit (texture × B / D)</source>
        <translation>&amp;Rééclairée (texture × B / D)</translation>
    </message>
    <message>
        <source>Relit, r&amp;atio only (texture × B / B_orig)</source>
        <translation>Rééclairée, r&amp;apport seul (texture × B / B_orig)</translation>
    </message>
    <message>
        <source>Original &amp;photo</source>
        <translation>&amp;Photo d&apos;origine</translation>
    </message>
    <message>
        <source>&amp;Unoccluded textures (shadows removed)</source>
        <translation>Textures &amp;sans ombres (ombres retirées)</translation>
    </message>
    <message>
        <source>Radiosity &amp;B</source>
        <translation>Radiosité &amp;B</translation>
    </message>
    <message>
        <source>Display factor &amp;D</source>
        <translation>Facteur d&apos;affichage &amp;D</translation>
    </message>
    <message>
        <source>&amp;Leaf outlines</source>
        <translation>&amp;Contours des éléments</translation>
    </message>
    <message>
        <source>&amp;False colour luminance</source>
        <translation>Luminance en &amp;fausses couleurs</translation>
    </message>
    <message>
        <source>Exposure +½ EV</source>
        <translation>Exposition +½ IL</translation>
    </message>
    <message>
        <source>Exposure −½ EV</source>
        <translation>Exposition −½ IL</translation>
    </message>
    <message>
        <source>Exposure of the &amp;photo</source>
        <translation>Exposition de la &amp;photo</translation>
    </message>
    <message>
        <source>&amp;Through the photo&apos;s camera</source>
        <translation>&amp;Par la caméra de la photo</translation>
    </message>
    <message>
        <source>Free &amp;orbit</source>
        <translation>&amp;Orbite libre</translation>
    </message>
    <message>
        <source>&amp;Lighting</source>
        <translation>É&amp;clairage</translation>
    </message>
    <message>
        <source>&amp;All lamps as photographed</source>
        <translation>&amp;Toutes les lampes comme photographiées</translation>
    </message>
    <message>
        <source>all lamps as photographed</source>
        <translation>toutes les lampes comme photographiées</translation>
    </message>
    <message>
        <source>All lamps &amp;off</source>
        <translation>Toutes les lampes é&amp;teintes</translation>
    </message>
    <message>
        <source>all lamps off</source>
        <translation>toutes les lampes éteintes</translation>
    </message>
    <message>
        <source>&amp;Help</source>
        <translation>&amp;Aide</translation>
    </message>
    <message>
        <source>&amp;About Relume</source>
        <translation>À &amp;propos de Relume</translation>
    </message>
    <message>
        <source>About Relume</source>
        <translation>À propos de Relume</translation>
    </message>
    <message>
        <source>&lt;b&gt;Relume&lt;/b&gt; relights photographed rooms: switch real lamps off, dim or tint them, add virtual lamps and objects, and see the photograph respond.&lt;br&gt;&lt;br&gt;Method: Loscos, Drettakis, Robert 2000, &lt;i&gt;Interactive virtual relighting of real scenes&lt;/i&gt; — hierarchical radiosity with clustering, real shadows removed from the photo textures, display of texture × B / D.</source>
        <translation>&lt;b&gt;Relume&lt;/b&gt; rééclaire des pièces photographiées : éteignez, atténuez ou teintez les vraies lampes, ajoutez des lampes et des objets virtuels, et voyez la photo réagir.&lt;br&gt;&lt;br&gt;Méthode : Loscos, Drettakis, Robert 2000, &lt;i&gt;Interactive virtual relighting of real scenes&lt;/i&gt; — radiosité hiérarchique avec regroupement, ombres réelles retirées des textures photo, affichage de texture × B / D.</translation>
    </message>
    <message>
        <source>Another job is running; wait for it or cancel it first.</source>
        <translation>Une autre tâche est en cours ; attendez-la ou annulez-la d&apos;abord.</translation>
    </message>
    <message>
        <source>Opening %1</source>
        <translation>Ouverture de %1</translation>
    </message>
    <message>
        <source>Opened %1</source>
        <translation>%1 ouvert</translation>
    </message>
    <message>
        <source>Saving %1</source>
        <translation>Enregistrement de %1</translation>
    </message>
    <message>
        <source>Saved %1</source>
        <translation>%1 enregistré</translation>
    </message>
    <message>
        <source>Unsaved edits</source>
        <translation>Modifications non enregistrées</translation>
    </message>
    <message>
        <source>%1 has unsaved edits. Save them first?</source>
        <translation>%1 a des modifications non enregistrées. Les enregistrer d&apos;abord ?</translation>
    </message>
    <message>
        <source>A job is running: cancel it before quitting.</source>
        <translation>Une tâche est en cours : annulez-la avant de quitter.</translation>
    </message>
    <message>
        <source>%1[*] — Relume</source>
        <translation>%1[*] — Relume</translation>
    </message>
    <message>
        <source>No room open</source>
        <translation>Aucune pièce ouverte</translation>
    </message>
    <message>
        <source>free orbit</source>
        <translation>orbite libre</translation>
    </message>
    <message>
        <source>photo camera</source>
        <translation>caméra de la photo</translation>
    </message>
    <message>
        <source>&amp;Language</source>
        <translation>&amp;Langue</translation>
    </message>
    <message>
        <source>System language</source>
        <translation>Langue du système</translation>
    </message>
    <message>
        <source>The language changes when Relume starts again.</source>
        <translation>La langue changera au prochain démarrage de Relume.</translation>
    </message>
    <message>
        <source>Objects</source>
        <translation>Objets</translation>
    </message>
    <message>
        <source>Add a &amp;virtual lamp (click a surface)</source>
        <translation>Ajouter une lampe &amp;virtuelle (cliquez sur une surface)</translation>
    </message>
    <message>
        <source>Add a &amp;box (click a floor)</source>
        <translation>Ajouter une &amp;boîte (cliquez sur un sol)</translation>
    </message>
    <message>
        <source>&amp;Delete the selected lamp or object</source>
        <translation>&amp;Supprimer la lampe ou l&apos;objet sélectionné</translation>
    </message>
    <message>
        <source>Reference patches</source>
        <translation>Patchs de référence</translation>
    </message>
    <message>
        <source>Autosave failed: %1</source>
        <translation>Échec de l&apos;enregistrement automatique : %1</translation>
    </message>
    <message>
        <source>Autosaving</source>
        <translation>Enregistrement automatique</translation>
    </message>
    <message>
        <source>Autosaved at %1</source>
        <translation>Enregistré automatiquement à %1</translation>
    </message>
    <message>
        <source>Recover unsaved edits</source>
        <translation>Récupérer les modifications non enregistrées</translation>
    </message>
    <message>
        <source>Relume did not close properly. Recover the edits to %1 autosaved at %2?</source>
        <translation>Relume ne s&apos;est pas fermé correctement. Récupérer les modifications de %1 enregistrées automatiquement le %2 ?</translation>
    </message>
    <message>
        <source>Recovering %1</source>
        <translation>Récupération de %1</translation>
    </message>
    <message>
        <source>Recovered the autosaved edits of %1: save them to keep them.</source>
        <translation>Modifications de %1 récupérées : enregistrez-les pour les conserver.</translation>
    </message>
    <message>
        <source>Cannot move the autosave %1 to %2</source>
        <translation>Impossible de déplacer l&apos;enregistrement automatique %1 vers %2</translation>
    </message>
    <message>
        <source>Occluded and &amp;frontier elements (§4.3)</source>
        <translation>Éléments occultés et &amp;frontière (§4.3)</translation>
    </message>
    <message>
        <source>&amp;Interactive mesh (faster edits, coarser shadows)</source>
        <translation>Maillage &amp;interactif (modifications plus rapides, ombres plus grossières)</translation>
    </message>
    <message>
        <source>Building the interactive mesh</source>
        <translation>Construction du maillage interactif</translation>
    </message>
    <message>
        <source>Building the refined mesh</source>
        <translation>Construction du maillage raffiné</translation>
    </message>
    <message>
        <source>%1 · %2 · %3, %4 leaves · %5 links · frame %6 ms · EV %7%8</source>
        <translation>%1 · %2 · %3, %4 feuilles · %5 liens · image %6 ms · IL %7%8</translation>
    </message>
    <message>
        <source>interactive mesh</source>
        <translation>maillage interactif</translation>
    </message>
    <message>
        <source>refined mesh</source>
        <translation>maillage raffiné</translation>
    </message>
    <message>
        <source>Inspector</source>
        <translation>Inspecteur</translation>
    </message>
    <message>
        <source>Photos</source>
        <translation>Photos</translation>
    </message>
    <message>
        <source>Reconstruction</source>
        <translation>Reconstruction</translation>
    </message>
    <message>
        <source>Model from clicks</source>
        <translation>Modèle à partir des clics</translation>
    </message>
    <message>
        <source>Sky</source>
        <translation>Ciel</translation>
    </message>
    <message>
        <source>Opened %1 (daylight: see the Sky panel)</source>
        <translation>%1 ouvert (lumière du jour : voir le panneau Ciel)</translation>
    </message>
    <message>
        <source>Save the daylight room as a project</source>
        <translation>Enregistrer la pièce en lumière du jour comme projet</translation>
    </message>
    <message>
        <source>A job is running: wait for it or cancel it, then save.</source>
        <translation>Une tâche est en cours : attendez-la ou annulez-la, puis enregistrez.</translation>
    </message>
</context>
<context>
    <name>relume::ObjectsPanel</name>
    <message>
        <source>New box</source>
        <translation>Nouvelle boîte</translation>
    </message>
    <message>
        <source> m</source>
        <translation> m</translation>
    </message>
    <message>
        <source>Albedo (diffuse reflectance) of the box</source>
        <translation>Albédo (réflectance diffuse) de la boîte</translation>
    </message>
    <message>
        <source>Width</source>
        <translation>Largeur</translation>
    </message>
    <message>
        <source>Depth</source>
        <translation>Profondeur</translation>
    </message>
    <message>
        <source>Height</source>
        <translation>Hauteur</translation>
    </message>
    <message>
        <source>Albedo</source>
        <translation>Albédo</translation>
    </message>
    <message>
        <source>Place a box (click a floor)</source>
        <translation>Poser une boîte (cliquez sur un sol)</translation>
    </message>
    <message>
        <source>Then click a floor or a table top in the viewport. Drag a box to move it along what it stands on.</source>
        <translation>Cliquez ensuite sur un sol ou un plateau de table dans la vue. Faites glisser une boîte pour la déplacer sur ce qui la porte.</translation>
    </message>
    <message>
        <source>Objects in the room</source>
        <translation>Objets dans la pièce</translation>
    </message>
    <message>
        <source>None yet.</source>
        <translation>Aucun pour l&apos;instant.</translation>
    </message>
    <message>
        <source>Albedo of the box</source>
        <translation>Albédo de la boîte</translation>
    </message>
    <message>
        <source>°</source>
        <translation>°</translation>
    </message>
    <message>
        <source>Turn about the vertical</source>
        <translation>Rotation autour de la verticale</translation>
    </message>
    <message>
        <source>Delete</source>
        <translation>Supprimer</translation>
    </message>
    <message>
        <source>Not turned: %1</source>
        <translation>Non tourné : %1</translation>
    </message>
    <message>
        <source>Place an OBJ mesh...</source>
        <translation>Poser un maillage OBJ...</translation>
    </message>
    <message>
        <source>A mesh in metres, +Z up, with the albedo above; it stands where you click.</source>
        <translation>Un maillage en mètres, +Z vers le haut, avec l&apos;albédo ci-dessus ; il se pose là où vous cliquez.</translation>
    </message>
    <message>
        <source>Place an OBJ mesh</source>
        <translation>Poser un maillage OBJ</translation>
    </message>
    <message>
        <source>Wavefront OBJ (*.obj)</source>
        <translation>Wavefront OBJ (*.obj)</translation>
    </message>
    <message>
        <source>%1: %2 triangles; the radiosity engine takes meshes of up to %3.</source>
        <translation>%1 : %2 triangles ; le moteur de radiosité accepte des maillages d&apos;au plus %3.</translation>
    </message>
    <message>
        <source>Image-based object</source>
        <translation>Objet à base d&apos;images</translation>
    </message>
    <message>
        <source>x </source>
        <translation>x </translation>
    </message>
    <message>
        <source>The mesh&apos;s units times this are metres</source>
        <translation>Les unités du maillage multipliées par ceci donnent des mètres</translation>
    </message>
    <message>
        <source>Scale</source>
        <translation>Échelle</translation>
    </message>
    <message>
        <source>Place an image-based object...</source>
        <translation>Placer un objet à base d&apos;images...</translation>
    </message>
    <message>
        <source>An image fan (relume ibr-fan writes them) or a mesh of any size (OBJ, PLY, glTF), drawn from images relit by the room&apos;s lamps; it stands where you click.</source>
        <translation>Un éventail d&apos;images (relume ibr-fan les écrit) ou un maillage de toute taille (OBJ, PLY, glTF), dessiné à partir d&apos;images rééclairées par les lampes de la pièce ; il se pose là où vous cliquez.</translation>
    </message>
    <message>
        <source>Place an image-based object</source>
        <translation>Placer un objet à base d&apos;images</translation>
    </message>
    <message>
        <source>Image fans and meshes (*.fan *.obj *.ply *.gltf *.glb)</source>
        <translation>Éventails d&apos;images et maillages (*.fan *.obj *.ply *.gltf *.glb)</translation>
    </message>
    <message>
        <source>Image-based objects in the room</source>
        <translation>Objets à base d&apos;images dans la pièce</translation>
    </message>
    <message>
        <source>Rendering the image fan of %1</source>
        <translation>Rendu de l&apos;éventail d&apos;images de %1</translation>
    </message>
    <message>
        <source>Another job is running: wait for it, or cancel it.</source>
        <translation>Une autre tâche est en cours : attendez-la ou annulez-la.</translation>
    </message>
    <message>
        <source>Scale (it keeps standing where it stands)</source>
        <translation>Échelle (l&apos;objet reste posé là où il est)</translation>
    </message>
    <message>
        <source>Not changed: %1</source>
        <translation>Non modifié : %1</translation>
    </message>
</context>
<context>
    <name>relume::PhotosPanel</name>
    <message>
        <source>Import folder...</source>
        <translation>Importer un dossier...</translation>
    </message>
    <message>
        <source>Import photos...</source>
        <translation>Importer des photos...</translation>
    </message>
    <message>
        <source>Merge brackets to HDR</source>
        <translation>Fusionner les séries en HDR</translation>
    </message>
    <message>
        <source>Each bracket of exposures becomes one radiance image (Debevec and Malik), beside its middle exposure: one photo per viewpoint, what reconstruction reads</source>
        <translation>Chaque série d&apos;expositions devient une image de radiance (Debevec et Malik), à côté de son exposition médiane : une photo par point de vue, ce que lit la reconstruction</translation>
    </message>
    <message>
        <source>No photos yet: import a folder of photos or brackets.</source>
        <translation>Pas encore de photos : importez un dossier de photos ou de séries.</translation>
    </message>
    <message>
        <source>Photo</source>
        <translation>Photo</translation>
    </message>
    <message>
        <source>Size</source>
        <translation>Taille</translation>
    </message>
    <message>
        <source>Camera</source>
        <translation>Appareil</translation>
    </message>
    <message>
        <source>Focal</source>
        <translation>Focale</translation>
    </message>
    <message>
        <source>Exposure</source>
        <translation>Exposition</translation>
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
        <translation>Série</translation>
    </message>
    <message>
        <source>Histogram of the selected photo</source>
        <translation>Histogramme de la photo choisie</translation>
    </message>
    <message>
        <source>Recovered response (no bracket merged yet)</source>
        <translation>Réponse retrouvée (aucune série fusionnée)</translation>
    </message>
    <message>
        <source> m</source>
        <translation> m</translation>
    </message>
    <message>
        <source>Inner corners</source>
        <translation>Coins intérieurs</translation>
    </message>
    <message>
        <source>square</source>
        <translation>case</translation>
    </message>
    <message>
        <source>Calibrate from the selected photos</source>
        <translation>Calibrer à partir des photos choisies</translation>
    </message>
    <message>
        <source>Photos of a flat checkerboard from several angles: focal length, principal point and lens distortion (OpenCV), written to the capture&apos;s intrinsics.json</source>
        <translation>Photos d&apos;un damier plan sous plusieurs angles : focale, point principal et distorsion de l&apos;objectif (OpenCV), écrits dans le fichier intrinsics.json de la prise de vue</translation>
    </message>
    <message>
        <source>Not calibrated.</source>
        <translation>Non calibré.</translation>
    </message>
    <message>
        <source>Histogram</source>
        <translation>Histogramme</translation>
    </message>
    <message>
        <source>Response curve</source>
        <translation>Courbe de réponse</translation>
    </message>
    <message>
        <source>Calibration</source>
        <translation>Calibration</translation>
    </message>
    <message>
        <source>Import a folder of photos</source>
        <translation>Importer un dossier de photos</translation>
    </message>
    <message>
        <source>Import photos</source>
        <translation>Importer des photos</translation>
    </message>
    <message>
        <source>Photos (*.jpg *.jpeg *.png *.tif *.tiff *.exr)</source>
        <translation>Photos (*.jpg *.jpeg *.png *.tif *.tiff *.exr)</translation>
    </message>
    <message>
        <source>%1 holds no photos (PNG, JPEG, TIFF or EXR).</source>
        <translation>%1 ne contient aucune photo (PNG, JPEG, TIFF ou EXR).</translation>
    </message>
    <message>
        <source>Importing photos: %1</source>
        <translation>Importation des photos : %1</translation>
    </message>
    <message>
        <source>Imported the photos; %1 could not be read (see the list).</source>
        <translation>Photos importées ; %1 illisibles (voir la liste).</translation>
    </message>
    <message>
        <source>Imported the photos.</source>
        <translation>Photos importées.</translation>
    </message>
    <message>
        <source>cannot be read</source>
        <translation>illisible</translation>
    </message>
    <message>
        <source>, radiance</source>
        <translation>, radiance</translation>
    </message>
    <message>
        <source>%1 mm</source>
        <translation>%1 mm</translation>
    </message>
    <message>
        <source>(%1 mm eq.)</source>
        <translation>(%1 mm éq.)</translation>
    </message>
    <message>
        <source>%1 EV</source>
        <translation>%1 IL</translation>
    </message>
    <message>
        <source>%1: %2 of %3</source>
        <translation>%1 : %2 sur %3</translation>
    </message>
    <message>
        <source>%1 photos, %2 viewpoints, brackets of several exposures: %3%4. Capture folder: %5</source>
        <translation>%1 photos, %2 points de vue, séries de plusieurs expositions : %3%4. Dossier de prise de vue : %5</translation>
    </message>
    <message>
        <source>; cannot be read: %1</source>
        <translation> ; illisibles : %1</translation>
    </message>
    <message>
        <source>Histogram of %1%2</source>
        <translation>Histogramme de %1%2</translation>
    </message>
    <message>
        <source> (as shown, exposed)</source>
        <translation> (tel qu&apos;affiché, exposé)</translation>
    </message>
    <message>
        <source>Recovered response, %1 exposures</source>
        <translation>Réponse retrouvée, %1 expositions</translation>
    </message>
    <message>
        <source>pixel value</source>
        <translation>valeur du pixel</translation>
    </message>
    <message>
        <source>exposure</source>
        <translation>exposition</translation>
    </message>
    <message>
        <source>No 8-bit photos to merge.</source>
        <translation>Aucune photo 8 bits à fusionner.</translation>
    </message>
    <message>
        <source>Merging brackets to HDR</source>
        <translation>Fusion des séries en HDR</translation>
    </message>
    <message>
        <source>Brackets merged to HDR: %1; viewpoints in %2: %3</source>
        <translation>Séries fusionnées en HDR : %1 ; points de vue dans %2 : %3</translation>
    </message>
    <message>
        <source>Select 3 or more photos of the checkerboard first.</source>
        <translation>Choisissez d&apos;abord au moins 3 photos du damier.</translation>
    </message>
    <message>
        <source>Calibrating the camera</source>
        <translation>Calibration de l&apos;appareil</translation>
    </message>
    <message>
        <source>Reprojection error %1 px over %2 photos.
fx %3, fy %4, cx %5, cy %6 px; k1 %7, k2 %8, p1 %9, p2 %10.%11
Written to %12</source>
        <translation>Erreur de reprojection %1 px sur %2 photos.
fx %3, fy %4, cx %5, cy %6 px ; k1 %7, k2 %8, p1 %9, p2 %10.%11
Écrit dans %12</translation>
    </message>
    <message>
        <source>
No checkerboard found in: %1</source>
        <translation>
Aucun damier trouvé dans : %1</translation>
    </message>
    <message>
        <source>Cannot read %1: %2</source>
        <translation>Impossible de lire %1 : %2</translation>
    </message>
</context>
<context>
    <name>relume::ReconstructionPanel</name>
    <message>
        <source>Choose...</source>
        <translation>Choisir...</translation>
    </message>
    <message>
        <source>Choose a folder</source>
        <translation>Choisir un dossier</translation>
    </message>
    <message>
        <source>Photos</source>
        <translation>Photos</translation>
    </message>
    <message>
        <source>One photo per viewpoint (8-bit; the merged photos of the Photos panel)</source>
        <translation>Une photo par point de vue (8 bits ; les photos fusionnées du panneau Photos)</translation>
    </message>
    <message>
        <source>Workspace</source>
        <translation>Dossier de travail</translation>
    </message>
    <message>
        <source>Where COLMAP&apos;s database and the model go (sparse/, workspace.json)</source>
        <translation>Où vont la base de COLMAP et le modèle (sparse/, workspace.json)</translation>
    </message>
    <message>
        <source>Run COLMAP</source>
        <translation>Lancer COLMAP</translation>
    </message>
    <message>
        <source>Features, matching and mapping on the CPU, as a job (Cancel stops COLMAP and writes nothing)</source>
        <translation>Points d&apos;intérêt, appariement et reconstruction sur le processeur, en tâche de fond (Annuler arrête COLMAP et n&apos;écrit rien)</translation>
    </message>
    <message>
        <source>No reconstruction yet.</source>
        <translation>Pas encore de reconstruction.</translation>
    </message>
    <message>
        <source>Photo</source>
        <translation>Photo</translation>
    </message>
    <message>
        <source>Registered</source>
        <translation>Recalée</translation>
    </message>
    <message>
        <source>Pick 2 points</source>
        <translation>Choisir 2 points</translation>
    </message>
    <message>
        <source>Click two points of the reconstruction whose distance you measured in the room</source>
        <translation>Cliquez deux points de la reconstruction dont vous avez mesuré la distance dans la pièce</translation>
    </message>
    <message>
        <source> m</source>
        <translation> m</translation>
    </message>
    <message>
        <source>Their distance in the room</source>
        <translation>Leur distance dans la pièce</translation>
    </message>
    <message>
        <source>Pick 3 floor points</source>
        <translation>Choisir 3 points du sol</translation>
    </message>
    <message>
        <source>Click three points on the floor: it becomes z = 0, +z up</source>
        <translation>Cliquez trois points du sol : il devient z = 0, +z vers le haut</translation>
    </message>
    <message>
        <source>Apply metric frame</source>
        <translation>Appliquer le repère métrique</translation>
    </message>
    <message>
        <source>Choose the folder of photos first.</source>
        <translation>Choisissez d&apos;abord le dossier des photos.</translation>
    </message>
    <message>
        <source>Choose a workspace folder first.</source>
        <translation>Choisissez d&apos;abord un dossier de travail.</translation>
    </message>
    <message>
        <source>Reconstructing with COLMAP</source>
        <translation>Reconstruction avec COLMAP</translation>
    </message>
    <message>
        <source>yes</source>
        <translation>oui</translation>
    </message>
    <message>
        <source>no: no pose found</source>
        <translation>non : aucune pose trouvée</translation>
    </message>
    <message>
        <source>%1 of %2 photos registered; %3 points; mean reprojection error %4 px. Model: %5</source>
        <translation>%1 photos sur %2 recalées ; %3 points ; erreur de reprojection moyenne %4 px. Modèle : %5</translation>
    </message>
    <message>
        <source>Scale points: %1; floor points: %2%3</source>
        <translation>Points d&apos;échelle : %1 ; points du sol : %2%3</translation>
    </message>
    <message>
        <source> (click points in the view)</source>
        <translation> (cliquez des points dans la vue)</translation>
    </message>
    <message>
        <source>Pick two points and their distance, and three floor points, first.</source>
        <translation>Choisissez d&apos;abord deux points et leur distance, et trois points du sol.</translation>
    </message>
    <message>
        <source>The model is in metres now, the floor at z = 0.</source>
        <translation>Le modèle est maintenant en mètres, le sol à z = 0.</translation>
    </message>
    <message>
        <source>Align to known cameras...</source>
        <translation>Aligner sur des caméras connues...</translation>
    </message>
    <message>
        <source>Put the model in the frame of known cameras: a room, a project, or another reconstruction whose photos have the same names (their camera centres are matched)</source>
        <translation>Placer le modèle dans le repère de caméras connues : une pièce, un projet ou une autre reconstruction dont les photos ont les mêmes noms (leurs centres de caméra sont appariés)</translation>
    </message>
    <message>
        <source>The room, project or reconstruction with the known cameras</source>
        <translation>La pièce, le projet ou la reconstruction aux caméras connues</translation>
    </message>
    <message>
        <source>Aligned to the %1 known cameras: camera centres %2 m apart (median), %3 m at most.</source>
        <translation>Aligné sur les %1 caméras connues : centres de caméra à %2 m (médiane), %3 m au plus.</translation>
    </message>
</context>
<context>
    <name>relume::ReferencesPanel</name>
    <message>
        <source>Polygon</source>
        <translation>Polygone</translation>
    </message>
    <message>
        <source>Automatic</source>
        <translation>Automatique</translation>
    </message>
    <message>
        <source>Yours</source>
        <translation>Le vôtre</translation>
    </message>
    <message>
        <source>Pick in the view</source>
        <translation>Choisir dans la vue</translation>
    </message>
    <message>
        <source>Then click a texel of the selected polygon: its shadowed elements that match no unshadowed neighbour take that texel&apos;s reflectance.</source>
        <translation>Cliquez ensuite sur un texel du polygone sélectionné : ses éléments ombrés sans voisin non ombré semblable prennent la réflectance de ce texel.</translation>
    </message>
    <message>
        <source>Back to the automatic choice for the selected polygon</source>
        <translation>Revenir au choix automatique pour le polygone sélectionné</translation>
    </message>
    <message>
        <source>No room open.</source>
        <translation>Aucune pièce ouverte.</translation>
    </message>
    <message>
        <source>Removing the real shadows again</source>
        <translation>Nouveau retrait des ombres réelles</translation>
    </message>
    <message>
        <source>Recompute</source>
        <translation>Recalculer</translation>
    </message>
    <message>
        <source>Recompute (changes pending)</source>
        <translation>Recalculer (modifications en attente)</translation>
    </message>
    <message>
        <source>Show occluded and frontier elements</source>
        <translation>Montrer les éléments occultés et la frontière</translation>
    </message>
    <message>
        <source>In the view: occluded elements in blue, the unshadowed frontier they take their colour from in yellow</source>
        <translation>Dans la vue : les éléments occultés en bleu, la frontière non ombrée dont ils prennent la couleur en jaune</translation>
    </message>
    <message>
        <source>Reference patches as plane coordinates u, v of their polygon, in metres</source>
        <translation>Zones de référence en coordonnées u, v du plan de leur polygone, en mètres</translation>
    </message>
    <message>
        <source>Paint a region</source>
        <translation>Peindre une région</translation>
    </message>
    <message>
        <source>Drag over a shadow of the selected polygon, then click the texel whose colour its occluded elements should take (for a shadow across two materials, say)</source>
        <translation>Glissez sur une ombre du polygone choisi, puis cliquez le texel dont ses éléments occultés doivent prendre la couleur (pour une ombre sur deux matériaux, par exemple)</translation>
    </message>
    <message>
        <source> m</source>
        <translation> m</translation>
    </message>
    <message>
        <source>Brush radius</source>
        <translation>Rayon du pinceau</translation>
    </message>
    <message>
        <source>Clear regions</source>
        <translation>Effacer les régions</translation>
    </message>
    <message>
        <source>Remove the regions painted on the selected polygon</source>
        <translation>Supprimer les régions peintes sur le polygone choisi</translation>
    </message>
    <message>
        <source>%1 occluded elements: %2 keep the light the solution traced as blocked, %3 took a similar-coloured unshadowed neighbour as reference, %4 their polygon&apos;s reference patch, %5 a painted region&apos;s. Choose a patch, or paint a region, where a shadow left a wrong colour.</source>
        <translation>%1 éléments occultés : %2 gardent la lumière que la solution a tracée comme bloquée, %3 ont pris pour référence un voisin non ombré de couleur proche, %4 la zone de référence de leur polygone, %5 celle d&apos;une région peinte. Choisissez une zone, ou peignez une région, là où une ombre a laissé une couleur fausse.</translation>
    </message>
    <message>
        <source>not seen</source>
        <translation>non vu</translation>
    </message>
    <message>
        <source>1 region</source>
        <translation>1 région</translation>
    </message>
    <message>
        <source>%1 regions</source>
        <translation>%1 régions</translation>
    </message>
    <message>
        <source>Remove the real shadows again with these reference patches: step 2 of the polygons whose choices changed, as a job</source>
        <translation>Retirer à nouveau les ombres réelles avec ces zones de référence : étape 2 des polygones dont le choix a changé, en tâche de fond</translation>
    </message>
</context>
<context>
    <name>relume::SkyPanel</name>
    <message>
        <source>Sky</source>
        <translation>Ciel</translation>
    </message>
    <message>
        <source>The room&apos;s measured skies, and the fisheye images or folders you added</source>
        <translation>Les ciels mesurés de la pièce, et les images fisheye ou dossiers que vous avez ajoutés</translation>
    </message>
    <message>
        <source>Image…</source>
        <translation>Image…</translation>
    </message>
    <message>
        <source>An HDR fisheye taken outside looking up (equidistant, 180°, image up = +Y)</source>
        <translation>Un fisheye HDR pris dehors vers le haut (équidistant, 180°, haut de l&apos;image = +Y)</translation>
    </message>
    <message>
        <source>Folder…</source>
        <translation>Dossier…</translation>
    </message>
    <message>
        <source>A folder of HDR fisheyes: a time-varying sky, played back in name order</source>
        <translation>Un dossier de fisheyes HDR : un ciel qui change, joué dans l&apos;ordre des noms</translation>
    </message>
    <message>
        <source>Method</source>
        <translation>Méthode</translation>
    </message>
    <message>
        <source>Near-field (basis solutions)</source>
        <translation>Champ proche (solutions de base)</translation>
    </message>
    <message>
        <source>Interactive (irradiance volume)</source>
        <translation>Interactive (volume d&apos;éclairement)</translation>
    </message>
    <message>
        <source>Distant (sky at infinity, for comparison)</source>
        <translation>Distante (ciel à l&apos;infini, pour comparer)</translation>
    </message>
    <message>
        <source>Near-field: the objects solved into every basis. Interactive: the paper&apos;s irradiance volume and 64 samples through the windows, nothing solved again. Distant: the baseline without windows.</source>
        <translation>Champ proche : les objets résolus dans chaque base. Interactive : le volume d&apos;éclairement de l&apos;article et 64 échantillons à travers les fenêtres, rien n&apos;est résolu à nouveau. Distante : la référence sans fenêtres.</translation>
    </message>
    <message>
        <source>Virtual objects</source>
        <translation>Objets virtuels</translation>
    </message>
    <message>
        <source>File…</source>
        <translation>Fichier…</translation>
    </message>
    <message>
        <source>Play</source>
        <translation>Lire</translation>
    </message>
    <message>
        <source>Play a folder&apos;s skies back, one frame after another</source>
        <translation>Lire les ciels d&apos;un dossier, une image après l&apos;autre</translation>
    </message>
    <message>
        <source>Original photo</source>
        <translation>Photo d&apos;origine</translation>
    </message>
    <message>
        <source>Show the photograph as taken, to compare</source>
        <translation>Montrer la photographie telle que prise, pour comparer</translation>
    </message>
    <message>
        <source>Sky image</source>
        <translation>Image du ciel</translation>
    </message>
    <message>
        <source>HDR images (*.exr *.hdr)</source>
        <translation>Images HDR (*.exr *.hdr)</translation>
    </message>
    <message>
        <source>Folder of sky images</source>
        <translation>Dossier d&apos;images du ciel</translation>
    </message>
    <message>
        <source>JSON (*.json)</source>
        <translation>JSON (*.json)</translation>
    </message>
    <message>
        <source>%1 (the photos&apos; sky)</source>
        <translation>%1 (le ciel des photos)</translation>
    </message>
    <message>
        <source>None</source>
        <translation>Aucun</translation>
    </message>
    <message>
        <source>As in variant %1</source>
        <translation>Comme dans la variante %1</translation>
    </message>
    <message>
        <source>Preparing daylight for %1</source>
        <translation>Préparation de la lumière du jour pour %1</translation>
    </message>
    <message>
        <source>%1 holds no HDR sky image (.exr or .hdr)</source>
        <translation>%1 ne contient aucune image HDR du ciel (.exr ou .hdr)</translation>
    </message>
    <message>
        <source>%1 (frames: %2)</source>
        <translation>%1 (images : %2)</translation>
    </message>
    <message>
        <source>Open a daylight room (one whose scene lists measured skies and windows) to relight it under another sky.</source>
        <translation>Ouvrez une pièce éclairée par le jour (dont la scène liste des ciels mesurés et des fenêtres) pour la rééclairer sous un autre ciel.</translation>
    </message>
    <message>
        <source>%1 — measured skies: %2; reflectances estimated from the main photo under %3.</source>
        <translation>%1 — ciels mesurés : %2 ; réflectances estimées d&apos;après la photo principale sous %3.</translation>
    </message>
    <message>
        <source>Relighting under %1</source>
        <translation>Rééclairage sous %1</translation>
    </message>
    <message>
        <source>photo</source>
        <translation>photo</translation>
    </message>
    <message>
        <source>The photograph as taken</source>
        <translation>La photographie telle que prise</translation>
    </message>
    <message>
        <source>Frame %1 of %2: %3, %4 s</source>
        <translation>Image %1 sur %2 : %3, %4 s</translation>
    </message>
    <message>
        <source>%1, rendered in %2 s</source>
        <translation>%1, rendu en %2 s</translation>
    </message>
    <message>
        <source>%1: the sun&apos;s pixels are clipped (at 65504, half float&apos;s largest value, or saturated): its light is understated and its colour shifted.</source>
        <translation>%1 : les pixels du soleil sont écrêtés (à 65504, la plus grande valeur du demi-flottant, ou saturés) : sa lumière est sous-estimée et sa couleur décalée.</translation>
    </message>
    <message>
        <source>Not rendered (%1): the image shows the setting before</source>
        <translation>Pas rendu (%1) : l&apos;image montre le réglage précédent</translation>
    </message>
    <message>
        <source>Variant %1 left out: %2</source>
        <translation>Variante %1 écartée : %2</translation>
    </message>
    <message>
        <source>Lamps on beside the daylight</source>
        <translation>Lampes allumées en plus de la lumière du jour</translation>
    </message>
    <message>
        <source>Check a lamp to switch it on at the radiance the room gives it (the photos are taken with the lamps off)</source>
        <translation>Cochez une lampe pour l’allumer à la luminance que la pièce lui donne (les photos sont prises lampes éteintes)</translation>
    </message>
    <message>
        <source>Lamp %1</source>
        <translation>Lampe %1</translation>
    </message>
    <message>
        <source>The room gives no radiance for this lamp, and a daylight photo (lamps off) cannot tell it</source>
        <translation>La pièce ne donne pas de luminance pour cette lampe, et une photo en lumière du jour (lampes éteintes) ne peut pas l’indiquer</translation>
    </message>
    <message>
        <source>Lamps (left out: the distant method is the sky alone)</source>
        <translation>Lampes (écartées : la méthode distante est le ciel seul)</translation>
    </message>
    <message>
        <source>Lamps (left out: the interactive path lights virtual objects by daylight only; choose near-field)</source>
        <translation>Lampes (écartées : le chemin interactif n’éclaire les objets virtuels qu’à la lumière du jour ; choisissez le champ proche)</translation>
    </message>
    <message>
        <source>Virtual objects and lamps</source>
        <translation>Objets et lampes virtuels</translation>
    </message>
    <message>
        <source>A JSON file with virtual_objects (boxes or OBJ meshes with their albedo) and/or virtual_lights (lamps, lit with the near-field method)</source>
        <translation>Un fichier JSON avec virtual_objects (boîtes ou maillages OBJ avec leur albédo) et/ou virtual_lights (lampes, éclairées par la méthode en champ proche)</translation>
    </message>
    <message>
        <source>The virtual lamps of %1 are left out: they are lit with the near-field method only</source>
        <translation>Les lampes virtuelles de %1 sont laissées de côté : elles ne sont éclairées que par la méthode en champ proche</translation>
    </message>
    <message>
        <source>Variant %1: its virtual lamps are left out: %2</source>
        <translation>Variante %1 : ses lampes virtuelles sont laissées de côté : %2</translation>
    </message>
    <message>
        <source>The virtual lamps of %1 are left out: %2</source>
        <translation>Les lampes virtuelles de %1 sont laissées de côté : %2</translation>
    </message>
    <message>
        <source>Saving %1</source>
        <translation>Enregistrement de %1</translation>
    </message>
    <message>
        <source>Saved %1 (its daylight session kept: it opens without solving again)</source>
        <translation>%1 enregistré (sa session de lumière du jour est conservée : il s’ouvre sans nouveau calcul)</translation>
    </message>
    <message>
        <source>Drag a virtual object&apos;s cross to move it over the floor</source>
        <translation>Faites glisser la croix d’un objet virtuel pour le déplacer sur le sol</translation>
    </message>
    <message>
        <source>the cursor points above the plane %1 stands on</source>
        <translation>le curseur pointe au-dessus du plan sur lequel repose %1</translation>
    </message>
    <message>
        <source>the cursor points at %1, in front of the plane %2 stands on</source>
        <translation>le curseur pointe sur %1, devant le plan sur lequel repose %2</translation>
    </message>
    <message>
        <source>Not moved: %1</source>
        <translation>Non déplacé : %1</translation>
    </message>
    <message>
        <source>%1, rendered in %2 ms</source>
        <translation>%1, rendu en %2 ms</translation>
    </message>
    <message>
        <source>OpenGL</source>
        <translation>OpenGL</translation>
    </message>
    <message>
        <source>Draw the interactive method with OpenGL: a shadow map per sample through the windows and per direction of the sun&apos;s disc, as in the paper (the same light as the CPU path, drawn faster)</source>
        <translation>Dessiner la méthode interactive avec OpenGL : une carte d&apos;ombres par échantillon à travers les fenêtres et par direction du disque solaire, comme dans l&apos;article (la même lumière que le chemin CPU, dessinée plus vite)</translation>
    </message>
    <message>
        <source>OpenGL cannot draw the daylight view (%1): the CPU path draws it</source>
        <translation>OpenGL ne peut pas dessiner la vue en lumière du jour (%1) : le chemin CPU la dessine</translation>
    </message>
    <message>
        <source>Virtual lamp %1 of %2 is not saved: its photometric file %3 is gone</source>
        <translation>La lampe virtuelle %1 de %2 n&apos;est pas enregistrée : son fichier photométrique %3 a disparu</translation>
    </message>
    <message>
        <source>Lamps (left out: image-based objects are lit by daylight only)</source>
        <translation>Lampes (écartées : les objets à base d&apos;images ne sont éclairés qu’à la lumière du jour)</translation>
    </message>
    <message>
        <source>The image-based objects of %1 are left out: they are drawn by the near-field and interactive methods</source>
        <translation>Les objets à base d&apos;images de %1 sont laissés de côté : ils sont dessinés par les méthodes en champ proche et interactive</translation>
    </message>
    <message>
        <source>The virtual lamps of %1 are left out: its image-based objects are lit by daylight only</source>
        <translation>Les lampes virtuelles de %1 sont laissées de côté : ses objets à base d&apos;images ne sont éclairés qu’à la lumière du jour</translation>
    </message>
    <message>
        <source>Image-based object %1 of %2 is not saved: its fan file %3 is gone</source>
        <translation>L&apos;objet à base d&apos;images %1 de %2 n&apos;est pas enregistré : son fichier d&apos;éventail %3 a disparu</translation>
    </message>
    <message>
        <source>%1: the sun&apos;s pixels are clipped (at 65504, half float&apos;s largest value, or saturated): its light is understated (its colour is taken from its pixels that did not clip).</source>
        <translation>%1 : les pixels du soleil sont écrêtés (à 65504, la plus grande valeur du demi-flottant, ou saturés) : sa lumière est sous-estimée (sa couleur est prise de ses pixels non écrêtés).</translation>
    </message>
    <message>
        <source>The lens the fisheye images and folders you add are read through: the ideal one (equidistant, 180°, the circle filling the image) or your sky camera&apos;s, calibrated with `relume calibrate --fisheye`</source>
        <translation>L&apos;objectif à travers lequel sont lues les images fisheye et les dossiers que vous ajoutez : l&apos;objectif idéal (équidistant, 180°, le cercle remplissant l&apos;image) ou celui de votre caméra de ciel, étalonné avec `relume calibrate --fisheye`</translation>
    </message>
    <message>
        <source>Calibrated lens…</source>
        <translation>Objectif étalonné…</translation>
    </message>
    <message>
        <source>Calibrated fisheye lens</source>
        <translation>Objectif fisheye étalonné</translation>
    </message>
    <message>
        <source>Ideal lens (equidistant, 180°)</source>
        <translation>Objectif idéal (équidistant, 180°)</translation>
    </message>
    <message>
        <source>Lens: ideal</source>
        <translation>Objectif : idéal</translation>
    </message>
    <message>
        <source>Lens: %1</source>
        <translation>Objectif : %1</translation>
    </message>
    <message>
        <source>%1 (read through the lens %2)</source>
        <translation>%1 (lu à travers l&apos;objectif %2)</translation>
    </message>
</context>
<context>
    <name>relume::ViewportWidget</name>
    <message>
        <source>Open a room or a project (File &gt; Open) to relight it.</source>
        <translation>Ouvrez une pièce ou un projet (Fichier &gt; Ouvrir) pour la rééclairer.</translation>
    </message>
    <message>
        <source>luminance</source>
        <translation>luminance</translation>
    </message>
</context>
</TS>
