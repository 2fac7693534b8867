"""Players in the browser: a profile page with ratings, a rating graph drawn by uPlot, recent
matches with every rack's replay; who is online in the lobby; a challenge sent from one browser
and accepted in another (both land on the table); a 6-red snooker table and a three-cushion
race to 5 points made with the lobby's form, their options on the table, played to the end
through the API (the simple shot picker) while the table page shows the result."""

from __future__ import annotations

from playwright.sync_api import Page

from server.protocol.ids import SNOOKER_REDS, THREE_CUSHION_TARGETS
from tests.e2e.conftest import (
    Api,
    Server,
    artefact,
    both_play,
    drawn_balls,
    join_as,
    name_at_home,
    screenshot,
    unique_name,
    wait_shown,
)

#: Inputs after which a match played by the picker is taken to be stuck.
MOST_INPUTS = 200


def finish(apis: list[Api], table_id: str) -> dict:
    """Play the simple shot picker for whichever player is to act until the match is over."""
    by_id = {
        api.page.evaluate("JSON.parse(localStorage.getItem('billiards.player')).id"): api
        for api in apis
    }
    for _ in range(MOST_INPUTS):
        view = apis[0].table(table_id)
        if view["status"] == "over":
            return view
        seat = view["next"]["seat"]
        by_id[view["seats"][seat]["id"]].play_picked(table_id)
    raise AssertionError(f"table {table_id} not over after {MOST_INPUTS} inputs")


def at_home(open_page, server: Server, prefix: str, who: str, **context) -> tuple[Page, str]:
    """A new player on the home page (its own browser context): the page and the name."""
    page = open_page("/", who=who, **context)
    name_at_home(page, server, prefix)
    return page, page.evaluate("JSON.parse(localStorage.getItem('billiards.player')).name")


def online_entry(page: Page, name: str):
    """The lobby's line for `name` in the list of who is online (once a snapshot has it)."""
    entry = page.locator("#people li", has=page.get_by_role("link", name=name, exact=True))
    entry.wait_for(timeout=30_000)  # snapshots come within the lobby's refresh (10 s)
    return entry


def test_the_profile_page_shows_ratings_graph_and_matches_with_replays(open_page, server, console):
    ada_page, bob_page = open_page("/", who="Ada"), open_page("/", who="Bob")
    ada, bob = Api(ada_page, server), Api(bob_page, server)
    ada_name = ada.sign_in(unique_name("Pr"))["name"]
    bob_name = bob.sign_in(unique_name("Po"))["name"]
    # A three-cushion race to 2 games of 1 point (a replay per game), then three nine-ball
    # matches decided by resigning (Bob wins two, loses the last): two games on the graph.
    carom = ada.call("POST", "/api/tables", {"game": "three_cushion", "target": 1, "race_to": 2})
    bob.call("POST", f"/api/tables/{carom['id']}/join")
    over = finish([ada, bob], carom["id"])
    for loser in (ada, ada, bob):
        pool = ada.call("POST", "/api/tables", {"game": "nineball"})
        bob.call("POST", f"/api/tables/{pool['id']}/join")
        both_play([ada, bob], pool["id"])  # a match resigned before that is not rated
        loser.call("POST", f"/api/tables/{pool['id']}/resign")
    page = ada_page
    page.goto(f"{server.url}/player/{bob_name.lower()}")  # names that read alike are one
    page.wait_for_function("window.billiards?.profile || window.billiards?.error")
    assert page.locator("#player-name").inner_text() == bob_name
    assert page.url.endswith(f"/player/{bob_name}")  # the holder's own spelling
    assert "online now" in page.locator("#seen").inner_text()
    ratings = page.locator("#ratings tbody tr")
    assert ratings.count() == 2
    carom_row = page.locator("#ratings tbody tr", has_text="Three-cushion").inner_text()
    assert "provisional" in carom_row
    profile = page.evaluate("window.billiards.profile")
    assert str(round(profile["ratings"]["three_cushion"]["rating"])) in carom_row
    # The graph: uPlot drew a canvas with a series per game, a point per rated match.
    graph = page.evaluate(
        """() => {
            const u = window.billiards.graph;
            const canvas = document.querySelector('#rating-graph canvas');
            return {series: u.series.map((s) => s.label), points: u.data[0], width: canvas.width};
        }"""
    )
    assert graph["series"] == ["date", "Nine-ball", "Three-cushion"]
    assert graph["points"] == [p["at"] for p in profile["history"]] and len(graph["points"]) == 4
    assert graph["width"] > 200
    # Matches, newest first: opponent, result, score, rating change, every rack's replay.
    rows = page.locator("#matches tbody tr")
    assert rows.count() == 4
    first, second = rows.nth(0).inner_text(), rows.nth(3).inner_text()
    assert "Nine-ball" in first and "Lost (resigned)" in first and "−" in first
    assert "Won (resigned)" in rows.nth(1).inner_text() and "+" in rows.nth(1).inner_text()
    assert "Three-cushion" in second and ("Won" if over["winner"] == 1 else "Lost") in second
    racks = over["racks_won"]
    assert f"{racks[1]}–{racks[0]}" in second
    links = rows.nth(3).locator(".replay-links a")
    assert links.count() == len(over["replays"]) >= 2
    assert links.first.get_attribute("href") == f"/replay/{over['replays'][0]}"
    opponent = rows.nth(0).get_by_role("link", name=ada_name)
    assert opponent.get_attribute("href") == f"/player/{ada_name}"
    page.screenshot(path=str(artefact("players-profile")), full_page=True)
    links.first.click()
    page.wait_for_url("**/replay/*")
    page.wait_for_function("window.billiards.shots > 0", timeout=60_000)  # the rack's shots
    # A name nobody has: a clear answer, not a blank page.
    console.allow("404")
    page.goto(f"{server.url}/player/Nobody{unique_name('x')}")
    page.wait_for_selector("#profile-error:not(:empty)")
    assert "No player here goes by that name" in page.locator("#profile-error").inner_text()


def test_the_lobby_says_who_is_online_and_what_each_does(open_page, server, console):
    ada, ada_name = at_home(open_page, server, "On", "Ada")
    bob, bob_name = at_home(open_page, server, "Ow", "Bob")
    entry = online_entry(ada, bob_name)
    assert "in the lobby" in entry.inner_text()
    assert entry.get_by_role("link", name=bob_name).get_attribute("href") == f"/player/{bob_name}"
    assert "(you)" in online_entry(ada, ada_name).inner_text()
    bob.locator("#games .card", has_text="Eight-ball").get_by_role(
        "button", name="Quick match"
    ).click()
    bob.wait_for_selector("text=Waiting for an opponent")
    ada.wait_for_function(
        "(id) => document.querySelector(`#people li[data-player='${id}'] .doing.waiting`)",
        arg=bob.evaluate("JSON.parse(localStorage.getItem('billiards.player')).id"),
        timeout=30_000,
    )
    assert "waiting for a quick match" in online_entry(ada, bob_name).inner_text()
    ada.screenshot(path=str(artefact("players-online")), full_page=True)


def test_the_own_name_is_marked_as_soon_as_the_page_knows_its_player(open_page, server):
    page, name = at_home(open_page, server, "Me", "Ada")
    online_entry(page, name)
    # Reloaded, the page draws the lobby's last snapshot (from the relay's buffer) before the
    # server has said who its player is (that answer held back here): drawn for nobody.
    held = []
    page.route("**/api/me", lambda route: held.append(route))
    page.reload()
    entry = online_entry(page, name)
    assert entry.get_by_role("button", name=f"Challenge {name}").count() == 1
    while not held:
        page.wait_for_timeout(50)
    held.pop().continue_()
    page.wait_for_function("document.getElementById('who').textContent !== ''")
    # The same snapshot, drawn again for the player: no challenge to oneself.
    assert "(you)" in entry.inner_text()
    assert entry.get_by_role("button").count() == 0


def test_a_challenge_is_sent_seen_and_accepted_and_both_land_on_the_table(
    browser, open_page, server
):
    ada, _ = at_home(open_page, server, "Ch", "Ada")
    context = browser.new_context(viewport={"width": 1280, "height": 800}, service_workers="block")
    context.grant_permissions(["notifications"], origin=server.url)
    # The notifications the page makes, counted (headless Chromium shows none).
    context.add_init_script(
        """window.notes = []; const Real = window.Notification;
           window.Notification = class extends Real {
             constructor(title, options) { window.notes.push(title); super(title, options); } };"""
    )
    bob = open_page("/", who="Bob", context=context)
    name_at_home(bob, server, "Cb")
    bob_name = bob.evaluate("JSON.parse(localStorage.getItem('billiards.player')).name")
    online_entry(ada, bob_name).get_by_role("button", name=f"Challenge {bob_name}").click()
    form = ada.locator("#challenge-form")
    form.locator("select[name=game]").select_option("snooker")
    reds = form.locator("select[name=reds]")
    assert reds.locator("option").all_inner_texts() == [f"{n} reds" for n in SNOOKER_REDS]
    reds.select_option("6")
    form.locator("input[name=race_to]").fill("2")
    screenshot(ada, "players-challenge-form")
    form.get_by_role("button", name="Send the challenge").click()
    ada.wait_for_selector(".challenge.sent")
    # Bob sees it at once, in the page and as a notification.
    received = bob.locator(".challenge.received")
    received.wait_for(timeout=10_000)
    text = received.inner_text()
    assert (
        "challenges you" in text and "Snooker" in text and "6 reds" in text and "race to 2" in text
    )
    bob.wait_for_function("window.notes.length === 1")
    screenshot(bob, "players-challenge-received")
    received.get_by_role("button", name="Accept").click()
    for page in (ada, bob):
        page.wait_for_url("**/table/*", timeout=30_000)
        wait_shown(page)
    assert ada.url == bob.url
    view = Api(ada, server).table(ada.url.rsplit("/", 1)[1])
    assert view["status"] == "playing" and view["options"]["reds"] == 6
    assert view["options"]["race_to"] == 2
    assert sum(ball.startswith("red") for ball in drawn_balls(bob)) == 6
    screenshot(bob, "players-challenge-table")
    context.close()


def test_a_challenge_declined_and_one_cancelled(open_page, server):
    ada, _ = at_home(open_page, server, "Cd", "Ada")
    bob, bob_name = at_home(open_page, server, "Ce", "Bob")
    challenge = online_entry(ada, bob_name).get_by_role("button", name=f"Challenge {bob_name}")
    for answer in ("Decline", "Cancel"):
        challenge.click()
        ada.locator("#challenge-form").get_by_role("button", name="Send the challenge").click()
        received = bob.locator(".challenge.received")
        received.wait_for(timeout=10_000)
        if answer == "Decline":
            received.get_by_role("button", name="Decline").click()
            ada.wait_for_selector(".challenge-notice:has-text('declined')", timeout=10_000)
        else:
            ada.locator(".challenge.sent").get_by_role("button", name="Cancel").click()
            bob.wait_for_selector(".challenge-notice:has-text('withdrew')", timeout=10_000)
        for page in (ada, bob):
            page.wait_for_selector(".challenge", state="detached", timeout=10_000)
    assert ada.url.endswith("/") and bob.url.endswith("/")


def create_with_form(page: Page, game: str, **options: str) -> str:
    """Make a table of `game` with the lobby's form and these option values; its id."""
    page.select_option("#create-game", game)
    for name, value in options.items():
        page.select_option(f"#create-options select[name={name}]", value)
    page.click("#create-form button[type=submit]")
    page.wait_for_url("**/table/*")
    wait_shown(page)
    return page.url.rsplit("/", 1)[1]


def test_a_six_red_snooker_match_from_the_lobby_form(open_page, server):
    ada, _ = at_home(open_page, server, "Sn", "Ada")
    table_id = create_with_form(ada, "snooker", reds="6")
    bob = open_page(f"/table/{table_id}", who="Bob")
    join_as(bob, unique_name("Sm"))
    wait_shown(ada, 2)
    assert sum(ball.startswith("red") for ball in drawn_balls(ada)) == 6
    assert "Points remaining: 75" in ada.locator("#players").inner_text()  # 6 x 8 + 27
    screenshot(ada, "players-snooker-six-reds")
    over = finish([Api(ada, server), Api(bob, server)], table_id)
    assert over["options"]["reds"] == 6
    ada.reload()  # (the page would animate every shot the picker played, one after another)
    ada.wait_for_selector("#status:has-text('Match over')", timeout=60_000)
    winner = over["seats"][over["winner"]]["name"]
    assert winner in ada.locator("#status").inner_text()
    screenshot(ada, "players-snooker-six-reds-over")


def test_a_three_cushion_race_to_five_from_the_lobby_form(open_page, server):
    ada, _ = at_home(open_page, server, "Tc", "Ada")
    ada.select_option("#create-game", "three_cushion")
    target = ada.locator("#create-options select[name=target]")
    assert target.locator("option").all_inner_texts() == [
        f"{n} points" for n in THREE_CUSHION_TARGETS
    ]
    table_id = create_with_form(ada, "three_cushion", target="5")
    bob = open_page(f"/table/{table_id}", who="Bob")
    join_as(bob, unique_name("Tb"))
    # The table says what it is played to, for both players.
    for page in (ada, bob):
        page.wait_for_selector(".options-words:has-text('To 5 points.')", timeout=30_000)
    over = finish([Api(ada, server), Api(bob, server)], table_id)
    assert over["options"]["target"] == 5 and over["state"]["target"] == 5
    assert max(over["state"]["scores"]) == 5
    ada.reload()  # (the page would animate every shot the picker played, one after another)
    ada.wait_for_selector("#status:has-text('Match over')", timeout=60_000)
    status = ada.locator("#status").inner_text()
    assert over["seats"][over["winner"]]["name"] in status and " 5" in status
    screenshot(ada, "players-three-cushion-over")


def test_the_bot_levels_show_each_level_s_rating(open_page, server):
    page = open_page("/", who="Ada")
    api = Api(page, server)
    api.sign_in(unique_name("Bt"))
    table = api.call("POST", "/api/tables", {"game": "nineball", "mode": "bot", "bot": "bot:2"})
    both_play([api, None], table["id"])  # a match resigned before that is not rated
    api.call("POST", f"/api/tables/{table['id']}/resign")
    rated = next(b for b in api.call("GET", "/api/bots")["bots"] if b["id"] == "bot:2")
    rating = rated["ratings"]["nineball"]
    page.reload()
    level = page.locator("#games .card", has_text="Nine-ball").locator("select.bot-level")
    option = level.locator("option[value='bot:2']")
    page.wait_for_function(
        "(o) => o.textContent.includes('·')", arg=option.element_handle(), timeout=10_000
    )
    assert option.inner_text() == f"Casual bot (level 2) · {round(rating['rating'])}?"
    unrated = page.locator("#games .card", has_text="Snooker").locator("option[value='bot:5']")
    assert unrated.inner_text() == "Strongest bot (level 5) · unrated"
    level.select_option("bot:2")
    rating_words = page.locator("#games .card", has_text="Nine-ball").locator(".bot-rating")
    expected = f"Rated {round(rating['rating'])} (provisional) in Nine-ball."
    assert rating_words.inner_text() == expected
    # Every card's list is as wide as its longest level needs: no level's words cut short.
    for select in page.locator("#games select.bot-level").element_handles():
        assert page.evaluate(FITS_ITS_OPTIONS, select), select.get_attribute("aria-label")
    screenshot(page, "players-bot-levels")


#: Whether select element `s` is as wide as it would be were its width not bound (by its
#: card): as wide as its longest option needs, so that each shows whole when chosen.
FITS_ITS_OPTIONS = """(s) => {
    const free = s.cloneNode(true);
    Object.assign(free.style, { maxWidth: "none", position: "absolute", visibility: "hidden" });
    document.body.append(free);
    const needed = free.getBoundingClientRect().width;
    free.remove();
    return s.getBoundingClientRect().width >= needed - 0.5;
}"""
