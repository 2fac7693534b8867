// /replay/{id}: not yet served by the game service; the page says so.
document.getElementById("status").textContent = "Replays are not available yet.";
